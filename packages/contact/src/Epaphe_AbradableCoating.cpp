#include "Epaphe_AbradableCoating.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"

namespace epaphe {

Teuchos::RCP<const Teuchos::ParameterList> CoatingMaterial::getValidParameters() {
  auto pl = Teuchos::rcp(new Teuchos::ParameterList("Coating"));
  deck::addDouble(*pl, "Thickness", 2e-3,
                  "t (m): the coating's thickness in front of the surface; 0: no coating (the surface acts rigid)",
                  0.0);
  deck::addDouble(*pl, "Young's modulus", 2e9, "E (Pa) of the coating's bar elements (Legrand et al. 2012)", 1e-300);
  deck::addDouble(*pl, "Yield stress", 1e6,
                  "sigma_Y (Pa), the initial yield stress in compression; 1e300: an elastic coating", 1e-300);
  deck::addDouble(*pl, "Hardening modulus", 0.0,
                  "H (Pa) of linear isotropic hardening, sigma_y = sigma_Y + H u_p / t; 0: perfectly plastic", 0.0);
  deck::addIntArray(*pl, "Elements", {0, 0},
                    "the element grid over the surface's parameters {along u, along v}: for a Casing surface "
                    "{around the circumference, along the axis}, e.g. {360, 4}; {0, 0} (the default): no coating");
  return pl;
}

CoatingMaterial CoatingMaterial::fromParameters(const Teuchos::ParameterList& pl, const std::string& where) {
  CoatingMaterial m;
  m.thickness = pl.get<double>("Thickness");
  m.youngsModulus = pl.get<double>("Young's modulus");
  m.yieldStress = pl.get<double>("Yield stress");
  m.hardeningModulus = pl.get<double>("Hardening modulus");
  const auto el = deck::getInts(pl, "Elements");
  const auto valid = getValidParameters();
  if (el.size() == 2 && el[0] == 0 && el[1] == 0) {  // no coating: then no other key may have been set
    for (const char* key : {"Thickness", "Young's modulus", "Yield stress", "Hardening modulus"})
      EPAPHE_REQUIRE(pl.get<double>(key) == valid->get<double>(key),
                     where << "->" << key
                           << " is set but the coating has no element grid: give 'Elements', e.g. "
                              "{360, 4} (around the circumference, along the axis of a Casing)");
    return CoatingMaterial{};
  }
  EPAPHE_REQUIRE(el.size() == 2 && el[0] >= 1 && el[1] >= 1,
                 where << "->Elements: {" << (el.empty() ? 0 : el[0]) << (el.size() > 1 ? ", ..." : "") << "} ("
                       << el.size() << " value(s)); give {along u, along v}, each >= 1, e.g. {360, 4}");
  EPAPHE_REQUIRE(static_cast<long>(el[0]) * el[1] <= 10'000'000,
                 where << "->Elements: " << el[0] << " x " << el[1] << " elements; at most 10 million");
  m.elements[0] = el[0];
  m.elements[1] = el[1];
  return m;
}

namespace {

// |S_u x S_v| of the surface at (u, v)
double areaDensity(const HostSurfaceView& S, double u, double v) {
  double P[3], Su[3], Sv[3], Suu[3], Suv[3], Svv[3];
  evaluate(S, u, v, P, Su, Sv, Suu, Suv, Svv);
  const double c[3] = {Su[1] * Sv[2] - Su[2] * Sv[1], Su[2] * Sv[0] - Su[0] * Sv[2], Su[0] * Sv[1] - Su[1] * Sv[0]};
  return std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

}  // namespace

CoatingViews makeCoatingViews(const std::vector<const BSplineSurface*>& surfaces,
                              const std::vector<CoatingMaterial>& materials) {
  EPAPHE_REQUIRE(surfaces.size() == materials.size(),
                 "coating: " << materials.size() << " coatings for " << surfaces.size() << " surfaces");
  const int ns = static_cast<int>(surfaces.size());
  CoatingViews c;
  c.law = Kokkos::View<double* [4]>("epaphe::coating::law", ns);
  c.grid = Kokkos::View<int* [3]>("epaphe::coating::grid", ns);
  int total = 0;
  for (int s = 0; s < ns; ++s) {
    const CoatingMaterial& m = materials[s];
    c.law(s, 0) = m.thickness;
    c.law(s, 1) = m.youngsModulus;
    c.law(s, 2) = m.yieldStress;
    c.law(s, 3) = m.hardeningModulus;
    c.grid(s, 0) = m.elements[0];
    c.grid(s, 1) = m.elements[1];
    c.grid(s, 2) = total;
    total += m.elements[0] * m.elements[1];
  }
  c.wear = Kokkos::View<double*>("epaphe::coating::wear", total);
  c.area = Kokkos::View<double*>("epaphe::coating::area", total);
  c.surface = Kokkos::View<int*>("epaphe::coating::surface", total);
  // 4-point Gauss-Legendre on [0, 1] per direction
  const double gx[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263};
  const double gw[4] = {0.1739274225687269, 0.3260725774312731, 0.3260725774312731, 0.1739274225687269};
  for (int s = 0; s < ns; ++s) {
    const int nu = c.grid(s, 0), nv = c.grid(s, 1);
    if (nu == 0) continue;
    const HostSurfaceView S = surfaces[s]->hostView();
    const double du = S.uMax() / nu, dv = S.vMax() / nv;
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        double a = 0.0;
        for (int p = 0; p < 4; ++p)
          for (int q = 0; q < 4; ++q) a += gw[p] * gw[q] * areaDensity(S, (i + gx[p]) * du, (j + gx[q]) * dv);
        const int e = c.grid(s, 2) + i * nv + j;
        c.area(e) = a * du * dv;
        c.surface(e) = s;
      }
  }
  return c;
}

void coatingCentres(const BSplineSurface& surface, const CoatingMaterial& m, const double axis[3],
                    const double center[3], std::vector<double>& angle, std::vector<double>& axial) {
  const HostSurfaceView S = surface.hostView();
  const int nu = m.elements[0], nv = m.elements[1];
  // a frame (e1, e2, axis) about the axis
  const double* a = axis;
  double e1[3] = {1.0, 0.0, 0.0};
  if (std::fabs(a[0]) > 0.9) e1[0] = 0.0, e1[1] = 1.0;
  double d = e1[0] * a[0] + e1[1] * a[1] + e1[2] * a[2];
  for (int k = 0; k < 3; ++k) e1[k] -= d * a[k];
  d = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  for (double& x : e1) x /= d;
  const double e2[3] = {a[1] * e1[2] - a[2] * e1[1], a[2] * e1[0] - a[0] * e1[2], a[0] * e1[1] - a[1] * e1[0]};
  auto centre = [&](int i, int j, double P[3]) {
    evaluatePoint(S, (i + 0.5) * S.uMax() / nu, (j + 0.5) * S.vMax() / nv, P);
    for (int k = 0; k < 3; ++k) P[k] -= center[k];
  };
  angle.assign(nu, 0.0);
  axial.assign(nv, 0.0);
  for (int i = 0; i < nu; ++i) {
    double P[3];
    centre(i, nv / 2, P);
    double phi = std::atan2(P[0] * e2[0] + P[1] * e2[1] + P[2] * e2[2], P[0] * e1[0] + P[1] * e1[1] + P[2] * e1[2]);
    if (phi < 0.0) phi += 2.0 * M_PI;
    angle[i] = phi;
  }
  for (int j = 0; j < nv; ++j) {
    double P[3];
    centre(0, j, P);
    axial[j] = P[0] * a[0] + P[1] * a[1] + P[2] * a[2];
  }
}

WearLobes wearLobes(const std::vector<double>& angle, const double* wear, int nu, int nv) {
  WearLobes r;
  std::vector<double> w(nu, 0.0);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) w[i] = std::max(w[i], wear[i * nv + j]);
  r.maxWear = nu > 0 ? *std::max_element(w.begin(), w.end()) : 0.0;
  if (!(r.maxWear > 0.0)) return r;
  // dominant harmonic
  double best = -1.0, phase = 0.0;
  for (int n = 1; n <= nu / 2; ++n) {
    std::complex<double> W = 0.0;
    for (int i = 0; i < nu; ++i) W += w[i] * std::polar(1.0, -2.0 * M_PI * n * i / nu);
    if (std::abs(W) > best * (1.0 + 1e-9)) {  // ties (to round-off): the smallest order
      best = std::abs(W);
      r.dominantOrder = n;
      phase = std::arg(W);
    }
  }
  if (best < 1e-12 * nu * r.maxWear) r.dominantOrder = 0;  // no harmonic content (uniform wear)
  for (int j = 0; j < r.dominantOrder; ++j) {
    const double n = r.dominantOrder;
    r.harmonicAngles.push_back(
        std::fmod(angle[0] + std::fmod(-phase / n + 2.0 * M_PI * j / n + 4.0 * M_PI, 2.0 * M_PI), 2.0 * M_PI));
  }
  std::sort(r.harmonicAngles.begin(), r.harmonicAngles.end());
  // lobes: circular runs above half the largest wear, started after a column below it
  const double half = 0.5 * r.maxWear;
  int start = -1;
  for (int i = 0; i < nu; ++i)
    if (!(w[i] > half)) {
      start = i;
      break;
    }
  if (start < 0) {  // worn all round: one lobe
    r.count = 1;
    r.angles.push_back(angle[std::max_element(w.begin(), w.end()) - w.begin()]);
    return r;
  }
  for (int k = 1; k <= nu; ++k) {
    const int i = (start + k) % nu;
    if (!(w[i] > half)) continue;
    int top = i;
    while (k < nu && w[(start + k + 1) % nu] > half) {
      ++k;
      if (w[(start + k) % nu] > w[top]) top = (start + k) % nu;
    }
    ++r.count;
    r.angles.push_back(angle[top]);
  }
  std::sort(r.angles.begin(), r.angles.end());
  return r;
}

}  // namespace epaphe
