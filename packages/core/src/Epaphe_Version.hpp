#pragma once
/// Epaphe's library: the classes and functions of every package (docs/developer/architecture.md).
namespace epaphe {
/// The library's version, the project's (CMakeLists.txt).
inline constexpr const char* version = "0.1.0";
}  // namespace epaphe
