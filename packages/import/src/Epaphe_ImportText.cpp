// Text lines and fields of the imported files (Epaphe_ImportDetails.hpp).
#include "Epaphe_ImportDetails.hpp"

#include <Kokkos_Core.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <future>
#include <limits>
#include <numeric>
#include <system_error>

namespace epaphe {
namespace Details {

TextLines::TextLines(const std::string& path, const std::string& what) : path_(path), in_(path) {
  EPAPHE_REQUIRE(in_.good(), path << ": cannot open the " << what << " file ("
                                  << (errno ? std::strerror(errno) : "unreadable")
                                  << "); check the path and that the FE code wrote it");
}

bool TextLines::next(std::string& line) {
  if (!std::getline(in_, line)) return false;
  ++line_;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

bool parseInt(const std::string& token, long long& value) {
  if (token.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtoll(token.c_str(), &end, 10);
  return errno == 0 && end == token.c_str() + token.size();
}

bool parseDouble(const std::string& token, double& value) {
  if (token.empty()) return false;
  std::string t = token;
  for (char& c : t)
    if (c == 'd' || c == 'D') c = 'e';  // Fortran 1.0D+03
  char* end = nullptr;
  value = std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size();
}

int parseDirection(const std::string& token) {
  const std::string t = upper(token);
  if (t == "1" || t == "X" || t == "DX") return 0;
  if (t == "2" || t == "Y" || t == "DY") return 1;
  if (t == "3" || t == "Z" || t == "DZ") return 2;
  return -1;
}

std::string siblingPath(const std::string& relativeTo, const std::string& file) {
  if (!file.empty() && file[0] == '/') return file;
  const auto slash = relativeTo.find_last_of('/');
  return slash == std::string::npos ? file : relativeTo.substr(0, slash + 1) + file;
}

}  // namespace Details
}  // namespace epaphe
