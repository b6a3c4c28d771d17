// The C++ half of the build-flags test firmware: constexpr and a template are C++ only, so this
// builds only when compiled as C++ (at the standard <firmware cxx_std> names).
template <int K>
constexpr int times(int x) { return K * x; }

extern "C" int twice(int x) { return times<2>(x); }
