// Configure-time check (CMakeLists.txt, EPAPHE_ARCH=auto): exits 0 when the machine that builds runs
// x86-64-v3 code (AVX, AVX2, BMI1/2, F16C, FMA, LZCNT, MOVBE, XSAVE). Compiled for the default target.
int main() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  return __builtin_cpu_supports("x86-64-v3") ? 0 : 1;
#else
  return 1;
#endif
}
