#include "Epaphe_CoatingOutput.hpp"

#include <cmath>
#include <cstdio>

#include "Epaphe_CoatingContact.hpp"
#include "Epaphe_Error.hpp"

namespace epaphe {

struct CoatingOutput::Coated {
  int surface = 0, first = 0, nu = 0, nv = 0;
  std::string name, group;  // the surface's name, /coating/<name>
  std::vector<double> angle, axial, record;
  std::unique_ptr<io::Series> time, wear;
};

CoatingOutput::CoatingOutput(io::Hdf5File& file, SurfaceContact& contact, const EnergyMonitor& monitor,
                             long long wearEvery, bool fresh)
    : file_(file),
      contact_(contact),
      monitor_(monitor),
      wearEvery_(wearEvery),
      plastic_(file, "/energy/plastic_dissipation", {}),
      elastic_(file, "/energy/coating_elastic", {}) {
  EPAPHE_REQUIRE(contact.coating() != nullptr && wearEvery > 0,
                 "coating output: no coating, or wear every " << wearEvery << " steps");
  const CoatingViews& cv = contact.coatingViews();
  const auto& surfaces = contact.detection().surfaces();
  for (int s = 0; s < static_cast<int>(surfaces.size()); ++s) {
    const ContactSurface& cs = surfaces[s];
    if (cv.grid(s, 0) == 0) continue;
    auto c = std::make_unique<Coated>();
    c->surface = s;
    c->nu = cv.grid(s, 0);
    c->nv = cv.grid(s, 1);
    c->first = cv.grid(s, 2);
    c->name = cs.surface->name();
    c->group = "/coating/" + c->name;
    coatingCentres(*cs.surface, cs.coating, cs.axis.data(), cs.center.data(), c->angle, c->axial);
    if (fresh) {
      file.writeDoubles(c->group + "/angle", c->angle);
      file.writeDoubles(c->group + "/axial", c->axial);
      file.writeInts(c->group + "/elements", std::vector<long long>{c->nu, c->nv});
      file.writeDoubles(c->group + "/area", {std::uint64_t(c->nu), std::uint64_t(c->nv)}, cv.area.data() + c->first);
      file.setAttribute(c->group, "thickness", cs.coating.thickness);
      file.setAttribute(c->group, "youngs_modulus", cs.coating.youngsModulus);
      file.setAttribute(c->group, "yield_stress", cs.coating.yieldStress);
      file.setAttribute(c->group, "hardening_modulus", cs.coating.hardeningModulus);
      writeMesh(*cs.surface, cs.coating, c->group);
    }
    c->time = std::make_unique<io::Series>(file, c->group + "/time", std::vector<std::uint64_t>{});
    c->wear = std::make_unique<io::Series>(file, c->group + "/wear",
                                           std::vector<std::uint64_t>{std::uint64_t(c->nu), std::uint64_t(c->nv)});
    c->record.resize(static_cast<std::size_t>(c->nu) * c->nv);
    coated_.push_back(std::move(c));
  }
}

CoatingOutput::~CoatingOutput() = default;

// The coating for ParaView: each element a quadrilateral at the coating's unworn front (the surface
// moved by t along its unit normal), the corners of its parameter cell; 4 points per element.
void CoatingOutput::writeMesh(const BSplineSurface& surface, const CoatingMaterial& m, const std::string& group) {
  const HostSurfaceView S = surface.hostView();
  const int nu = m.elements[0], nv = m.elements[1];
  std::vector<double> pts;
  pts.reserve(12 * static_cast<std::size_t>(nu) * nv);
  auto corner = [&](int i, int j) {
    double P[3], Su[3], Sv[3], Suu[3], Suv[3], Svv[3];
    evaluate(S, i * S.uMax() / nu, j * S.vMax() / nv, P, Su, Sv, Suu, Suv, Svv);
    double n[3] = {Su[1] * Sv[2] - Su[2] * Sv[1], Su[2] * Sv[0] - Su[0] * Sv[2], Su[0] * Sv[1] - Su[1] * Sv[0]};
    const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int d = 0; d < 3; ++d) pts.push_back(P[d] + m.thickness * S.orientation * n[d] / l);
  };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      corner(i, j);
      corner(i + 1, j);
      corner(i + 1, j + 1);
      corner(i, j + 1);
    }
  file_.writeDoubles(group + "/mesh/points", {4 * static_cast<std::uint64_t>(nu) * nv, 3}, pts.data());
  std::vector<long long> quads(4 * static_cast<std::size_t>(nu) * nv);
  for (std::size_t k = 0; k < quads.size(); ++k) quads[k] = static_cast<long long>(k);
  file_.writeInts(group + "/mesh/quads", {static_cast<std::uint64_t>(nu) * nv, 4}, quads.data());
}

std::vector<std::string> CoatingOutput::surfaces() const {
  std::vector<std::string> names;
  for (const auto& c : coated_) names.push_back(c->name);
  return names;
}

std::vector<io::Series*> CoatingOutput::series() {
  std::vector<io::Series*> r{&plastic_, &elastic_};
  for (auto& c : coated_) {
    r.push_back(c->time.get());
    r.push_back(c->wear.get());
  }
  return r;
}

void CoatingOutput::afterCorrect(ExplicitLoop& loop) {
  if (!monitor_.measures(loop)) return;
  ScopedPhase phase(loop.cost(), "output");
  const CoatingContact& law = *contact_.coating();
  const double plastic = law.plasticDissipation(), elastic = law.elasticEnergy();
  plastic_.append(&plastic);
  elastic_.append(&elastic);
  if (loop.step() % wearEvery_ != 0 && !loop.lastStep()) return;
  const auto wear = contact_.coatingViews().wear;
  const double t = loop.time();
  for (auto& c : coated_) {
    std::copy(wear.data() + c->first, wear.data() + c->first + c->record.size(), c->record.begin());
    c->time->append(&t);
    c->wear->append(c->record);
  }
}

void CoatingOutput::endRun(ExplicitLoop& loop) {
  if (loop.stepsDone() < loop.numSteps()) return;  // stopped: no final profile
  const auto wear = contact_.coatingViews().wear;
  const double dissipation = contact_.coating()->plasticDissipation();
  char buf[256];
  for (auto& c : coated_) {
    const WearLobes w = wearLobes(c->angle, wear.data() + c->first, c->nu, c->nv);
    file_.setAttribute(c->group, "max_wear", w.maxWear);
    file_.setAttribute(c->group, "plastic_dissipation", dissipation);
    file_.setAttribute(c->group, "lobes", static_cast<long long>(w.count));
    file_.setAttribute(c->group, "dominant_order", static_cast<long long>(w.dominantOrder));
    if (!file_.exists(c->group + "/lobe_angles")) {  // (a restart of a run that had ended: written already)
      file_.writeDoubles(c->group + "/lobe_angles", w.angles);
      file_.writeDoubles(c->group + "/harmonic_angles", w.harmonicAngles);
    }
    std::snprintf(buf, sizeof buf, "coating '%s': max wear %.4g um, plastic dissipation %.4g J, %d wear lobe(s)",
                  c->name.c_str(), 1e6 * w.maxWear, dissipation, w.count);
    std::string line = buf;
    for (std::size_t i = 0; i < w.angles.size() && i < 24; ++i) {
      std::snprintf(buf, sizeof buf, "%s%.1f", i == 0 ? " at " : ", ", w.angles[i] * 180.0 / M_PI);
      line += buf;
    }
    if (!w.angles.empty()) line += " deg";
    std::snprintf(buf, sizeof buf, "; dominant harmonic %d", w.dominantOrder);
    summary_.push_back(line + buf);
  }
}

}  // namespace epaphe
