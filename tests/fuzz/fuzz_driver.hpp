#pragma once
// A deterministic, dependency-free fuzzing loop for Epaphe's input readers (GCC has no libFuzzer).
//
// A target is a function `void target(const std::string& input, const std::string& seedPath)` (the
// seed file the input was mutated from) that must either return or throw epaphe::Error. The driver mutates seed files
// (bit flips, byte changes, deletions, insertions, duplications, truncations, numbers replaced by extreme values,
// splices of two seeds) with a seeded xorshift generator, so a run is reproducible from its seed and iteration number:
//
//   fuzz_x [--seconds S] [--iterations N] [--seed K] [--crash-dir DIR] [--replay FILE] SEED_FILES...
//
// Any other exception is a failure: the input is written to DIR/crash-<target>-<iteration> and the
// driver exits 1. A crash (signal) is caught by a handler that writes the input being run before
// re-raising; an input that runs longer than 10 s (a hang) is written and aborts the run likewise.
// Built with -DEPAPHE_LIBFUZZER and clang's -fsanitize=fuzzer, the same target is an
// LLVMFuzzerTestOneInput instead (the driver's main is left out).
#include "Epaphe_Error.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <typeinfo>
#include <unistd.h>
#include <vector>

namespace epaphe::fuzz {

class Rng {
public:
  explicit Rng(std::uint64_t seed) : s_(seed * 0x9E3779B97F4A7C15ull + 0x2545F4914F6CDD1Dull) { next(); }
  std::uint64_t next() {
    s_ ^= s_ << 13;
    s_ ^= s_ >> 7;
    s_ ^= s_ << 17;
    return s_;
  }
  std::size_t below(std::size_t n) { return n ? static_cast<std::size_t>(next() % n) : 0; }

private:
  std::uint64_t s_;
};

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// One to four mutations of `s` (`other`: a second seed for splicing).
inline std::string mutate(std::string s, const std::string& other, Rng& rng) {
  static const char* numbers[] = {
      "0",    "-0",   "-1",   "1e308",      "-1e308",     "1e-320",      "nan",
      "-nan", "inf",  "-inf", "2147483647", "2147483648", "-2147483649", "99999999999999999999",
      "1.5",  "0x10", "1e",   "--1",        "",           " ",           "1,2",
      "4"};
  static const char bytes[] = "0123456789-+.eE ,{}<>\"/=\n\t\\xyzNaI%*#";
  const int count = 1 + static_cast<int>(rng.below(4));
  for (int m = 0; m < count; ++m) {
    const std::size_t n = s.size();
    switch (rng.below(9)) {
      case 0:  // flip a bit
        if (n) s[rng.below(n)] ^= static_cast<char>(1u << rng.below(8));
        break;
      case 1:  // change a byte to a meaningful one
        if (n) s[rng.below(n)] = bytes[rng.below(sizeof bytes - 1)];
        break;
      case 2: {  // delete a range
        if (!n) break;
        const std::size_t at = rng.below(n);
        s.erase(at, 1 + rng.below(std::min<std::size_t>(64, n - at)));
        break;
      }
      case 3: {  // insert random bytes
        std::string ins(1 + rng.below(8), ' ');
        for (char& c : ins) c = static_cast<char>(rng.below(256));
        s.insert(rng.below(n + 1), ins);
        break;
      }
      case 4: {  // duplicate a chunk
        if (!n) break;
        const std::size_t at = rng.below(n), len = 1 + rng.below(std::min<std::size_t>(200, n - at));
        s.insert(rng.below(n + 1), s.substr(at, len));
        break;
      }
      case 5:  // truncate
        s.resize(rng.below(n + 1));
        break;
      case 6:
      case 7: {  // replace a number (or a word) by an extreme value
        if (!n) break;
        std::size_t at = rng.below(n);
        while (at < n && !(std::isdigit(static_cast<unsigned char>(s[at])) || s[at] == '-')) ++at;
        if (at >= n) break;
        std::size_t end = at + 1;
        while (end < n &&
               (std::isalnum(static_cast<unsigned char>(s[end])) || s[end] == '.' || s[end] == '-' || s[end] == '+'))
          ++end;
        s.replace(at, end - at, numbers[rng.below(sizeof numbers / sizeof *numbers)]);
        break;
      }
      case 8: {  // splice: our head, the other seed's tail
        if (other.empty()) break;
        s = s.substr(0, rng.below(n + 1)) + other.substr(rng.below(other.size()));
        break;
      }
    }
  }
  return s;
}

namespace detail {
inline std::string& current() {
  static std::string s;
  return s;
}
inline std::string& crashPath() {
  static std::string s;
  return s;
}
inline void writeCurrent() {
  if (FILE* f = std::fopen(crashPath().c_str(), "wb")) {
    std::fwrite(current().data(), 1, current().size(), f);
    std::fclose(f);
  }
}
extern "C" inline void onSignal(int sig) {
  writeCurrent();
  const char* msg =
      sig == SIGALRM ? "fuzz: an input ran longer than 10 s (hang), written to " : "fuzz: crash, input written to ";
  (void)!write(2, msg, std::strlen(msg));
  (void)!write(2, crashPath().data(), crashPath().size());
  (void)!write(2, "\n", 1);
  std::signal(sig == SIGALRM ? SIGABRT : sig, SIG_DFL);
  std::raise(sig == SIGALRM ? SIGABRT : sig);
}
}  // namespace detail

/// Runs the loop; returns the process exit code.
inline int runDriver(const std::string& name, int argc, char** argv,
                     const std::function<void(const std::string&, const std::string&)>& target) {
  double seconds = 10;
  long long iterations = -1;
  std::uint64_t seed = 1;
  std::string crashDir = ".", replay;
  std::vector<std::string> seeds;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seconds" && i + 1 < argc)
      seconds = std::atof(argv[++i]);
    else if (a == "--iterations" && i + 1 < argc)
      iterations = std::atoll(argv[++i]);
    else if (a == "--seed" && i + 1 < argc)
      seed = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--crash-dir" && i + 1 < argc)
      crashDir = argv[++i];
    else if (a == "--replay" && i + 1 < argc)
      replay = argv[++i];
    else
      seeds.push_back(a);
  }
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGALRM}) std::signal(sig, detail::onSignal);
  auto runOne = [&](const std::string& input, const std::string& from, long long it) -> bool {
    detail::current() = input;
    detail::crashPath() = crashDir + "/crash-" + name + "-" + std::to_string(it);
    alarm(10);
    try {
      target(input, from);
    } catch (const epaphe::Error&) {
    } catch (const std::exception& e) {
      alarm(0);
      detail::writeCurrent();
      std::cerr << "fuzz " << name << ": iteration " << it << " threw a " << typeid(e).name()
                << " that is not epaphe::Error: " << e.what() << "\n  input: " << detail::crashPath() << "\n";
      return false;
    } catch (...) {
      alarm(0);
      detail::writeCurrent();
      std::cerr << "fuzz " << name << ": iteration " << it
                << " threw a non-std exception\n  input: " << detail::crashPath() << "\n";
      return false;
    }
    alarm(0);
    return true;
  };
  if (!replay.empty()) {
    // --replay FILE SEED: FILE mutated from SEED (which tells the target the format and role)
    const bool ok = runOne(readFile(replay), seeds.empty() ? replay : seeds[0], 0);
    std::cout << "fuzz " << name << ": replay of " << replay << (ok ? ": PASSED\n" : ": FAILED\n");
    return ok ? 0 : 1;
  }
  std::vector<std::string> corpus;
  for (const auto& p : seeds) corpus.push_back(readFile(p));
  if (corpus.empty()) {
    std::cerr << "fuzz " << name << ": no seed files given\n";
    return 2;
  }
  Rng rng(seed);
  const auto start = std::chrono::steady_clock::now();
  long long it = 0;
  // Every seed as is first: they must pass (or fail cleanly) too.
  for (; it < static_cast<long long>(corpus.size()); ++it)
    if (!runOne(corpus[it], seeds[it], it)) return 1;
  for (;; ++it) {
    if (iterations >= 0 && it >= iterations) break;
    if (iterations < 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds)
      break;
    const std::size_t ia = rng.below(corpus.size());
    const std::string& b = corpus[rng.below(corpus.size())];
    if (!runOne(mutate(corpus[ia], b, rng), seeds[ia], it)) return 1;
  }
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "fuzz " << name << ": " << it << " inputs in " << el << " s (seed " << seed << ", " << corpus.size()
            << " seed files), only epaphe::Error raised: PASSED\n";
  return 0;
}

}  // namespace epaphe::fuzz
