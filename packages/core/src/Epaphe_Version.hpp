#pragma once
namespace epaphe {
inline constexpr const char* version = "0.1.0";
}
