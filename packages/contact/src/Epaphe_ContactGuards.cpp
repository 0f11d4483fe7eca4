#include "Epaphe_ContactGuards.hpp"

#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

#include <cmath>
#include <sstream>
#include <utility>

namespace epaphe {

ContactGuards::ContactGuards(const GuardOptions& options, std::vector<std::string> bodyNames, std::string origin)
    : opt_(options), bodies_(std::move(bodyNames)), origin_(std::move(origin)) {
  EPAPHE_REQUIRE(std::isfinite(opt_.rampTime) && opt_.rampTime >= 0.0,
                 origin_ << ": 'Contact->Penetration ramp time' = " << opt_.rampTime
                         << " s; give a finite time >= 0 (0: 100 time steps)");
}

std::string ContactGuards::surfaceName(const SurfaceContact& contact, int s) const {
  const auto& surfaces = contact.detection().surfaces();
  return s >= 0 && s < static_cast<int>(surfaces.size()) ? surfaces[s].surface->name() : std::string("?");
}

void ContactGuards::checkInitialVelocities(const SurfaceContact& contact, const std::vector<double>& speeds, double h,
                                           std::vector<std::string>& warnings) const {
  const double L = motionBound(contact);
  for (std::size_t b = 0; b < speeds.size() && b < bodies_.size(); ++b) {
    if (!(speeds[b] * h > L)) continue;
    std::ostringstream os;
    os << origin_ << ": body '" << bodies_[b] << "': its 'Initial velocity' (|v0| = " << speeds[b] << " m/s) moves it "
       << speeds[b] * h << " m per 'Time->Time step' (" << h << " s), more than the smallest "
       << "patch of the contact surfaces (" << L << " m, surface '"
       << surfaceName(contact, contact.detection().smallestPatchSurface())
       << "'): contact would be missed between two steps (tunnelling). Check the velocity's units (m/s), use "
          "'Time step' <= "
       << 0.5 * L / speeds[b] << " s, or set 'Contact->Allow large motion per step' = true";
    if (!opt_.allowLargeMotion) throw Error(os.str());
    warnings.push_back(os.str());
  }
}

PenetrationReport ContactGuards::checkInitialPenetration(SurfaceContact& contact, const DenseVector& q0, double h,
                                                         CostSplit& cost) const {
  PenetrationReport r;
  const double L = motionBound(contact);
  r.tolerance = 1e-6 * L;
  const auto warm = contact.warmStarts();
  contact.setTime(0.0);
  contact.measureGaps(q0, cost);
  const auto gap = contact.gap();
  const auto surf = contact.surfaceIndex();
  const DetectionViews& v = contact.detection().views();
  const int nc = contact.numNodes();
  r.depth.assign(static_cast<std::size_t>(nc), 0.0);
  for (int k = 0; k < nc; ++k) {
    r.facing += surf(k) >= 0;
    if (surf(k) < 0 || !(gap(k) < -r.tolerance)) continue;
    ++r.count;
    r.depth[k] = -gap(k);
    if (-gap(k) > r.deepest) {
      r.deepest = -gap(k);
      r.node = k;
      r.surface = surf(k);
      for (int d = 0; d < 3; ++d) r.position[d] = v.x(k, d);
    }
  }
  if (r.count > 0 && opt_.initialPenetration == InitialPenetration::ResolveGently) {
    const double T = opt_.rampTime > 0.0 ? opt_.rampTime : 100.0 * h;
    contact.setPenetrationOffsets(r.depth, T);  // the selected surfaces of this detection
  }
  contact.setWarmStarts(warm);  // the run starts as if unchecked
  if (r.count == 0 || opt_.initialPenetration == InitialPenetration::ResolveGently) return r;
  const int b = contact.nodeBlocks()[r.node];
  ErrorBuilder eb;
  eb << origin_ << ": the bodies start interpenetrating: " << r.count << " contact node(s) lie inside a surface at "
     << "t = 0 (deeper than " << r.tolerance << " m); the deepest, node " << contact.nodes()[r.node] << " of body '"
     << (b >= 0 && b < static_cast<int>(bodies_.size()) ? bodies_[b] : std::string("?")) << "' at (" << r.position[0]
     << ", " << r.position[1] << ", " << r.position[2] << ") m, is " << r.deepest << " m inside surface '"
     << surfaceName(contact, r.surface)
     << "'. Move the bodies or surfaces apart (check positions, 'Origin', 'Center', 'Radius' and 'Flip normal'), or "
        "set 'Contact->Initial penetration' = 'Resolve gently' to push them apart over 'Penetration ramp time'";
  eb.raise();
}

std::string ContactGuards::checkStep(const SurfaceContact& contact, const DenseVector& qNew, const DenseVector& qOld,
                                     double t, double h) const {
  const double L = motionBound(contact);
  const DetectionViews& v = contact.detection().views();
  const int nc = contact.numNodes();
  double worst = 0.0;
  int kw = -1;
  fence();
  for (int k = 0; k < nc; ++k) {
    double d2 = 0.0;
    for (int d = 0; d < 3; ++d) {
      const double dx = qNew(v.dof(k, d)) - qOld(v.dof(k, d));
      d2 += dx * dx;
    }
    if (d2 > worst) {  // NaN is left to the run's finiteness check
      worst = d2;
      kw = k;
    }
  }
  if (kw < 0 || std::sqrt(worst) <= L) return {};
  const int b = contact.nodeBlocks()[kw];
  std::ostringstream os;
  os << "contact node " << contact.nodes()[kw] << " of body '"
     << (b >= 0 && b < static_cast<int>(bodies_.size()) ? bodies_[b] : std::string("?")) << "' moved "
     << std::sqrt(worst) << " m in the step ending at t = " << t + h << " s (" << std::sqrt(worst) / h
     << " m/s), more than the smallest patch of the contact surfaces (" << L << " m, surface '"
     << surfaceName(contact, contact.detection().smallestPatchSurface()) << "')";
  if (contact.force()(kw) > 0.0) {  // pressed on a surface: not a node flying past it
    os << " while pressed on surface '" << surfaceName(contact, contact.surfaceIndex()(kw)) << "' (force "
       << contact.force()(kw) << " N, " << contact.numActive() << " node(s) in contact): the motion diverges in "
       << "contact, no node flew past a surface";
    const double rampEnd = contact.detection().penetrationRampEnd();
    if (rampEnd > 0.0 && t + h <= rampEnd + 10.0 * h) {  // the push that resolves initial penetrations
      os << ". The initial penetrations are pushed apart over 'Contact->Penetration ramp time' (ending at t = "
         << rampEnd << " s, " << rampEnd / h << " step(s)): the energy given grows as its inverse; lengthen it "
         << "(the default is 100 time steps)";
    }
    return os.str();
  }
  os << ": contact may be missed between two steps (tunnelling). Use a smaller 'Time->Time step' (<= "
     << 0.5 * h * L / std::sqrt(worst) << " s at this speed), or set 'Contact->Allow large motion per step' = true";
  return os.str();
}

}  // namespace epaphe
