// A run stopped by an error while its energy grows without bound (EnergyGrowth, in
// Epaphe_EnergyMonitor.hpp) says why
// (docs/user/divergence.md):
//   - where the energy came from over the rise: the contact forces' work (with the normal and the
//     friction forces' parts of the last step, and whether a surface turns), the external forces'
//     work, or neither: the integrator (its balance error, or an unstable step, whose half-step
//     energy stays while kinetic and strain energies grow);
//   - the growth rate (e-folding time) and the contact node with the largest force;
//   - whether the step matters: the deck run again at h/2 up to twice the stop time. When it
//     stops too, the divergence does not depend on the step: fed by contact or external work it
//     is a "physical instability of the model" (friction-fed when the friction part dominates);
//     when it reaches that time it is a "numerical instability", and h/2 is the step to use.
#include "Epaphe_Simulation.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_SceneCheck.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace epaphe {

using Teuchos::ParameterList;

namespace {

/// The contact part of the diagnosis: the normal and friction parts of the last step's contact
/// work and the node with the largest force. After the loop's rotation (a stop at the end of a
/// step) q_{n+1} is current() and q_{n-1} next(); before it (a stop in the correction) next()
/// and previous().
void describeContact(std::ostream& os, const ExplicitLoop& loop, const SurfaceContact& contact, bool turning) {
  const bool rotated = loop.stepsDone() > loop.step();
  const auto w = rotated ? contact.workIncrementSplit(loop.current(), loop.next())
                         : contact.workIncrementSplit(loop.next(), loop.previous());
  os << (turning ? "; a turning surface works on the bodies" : "") << "; in the last step the normal forces did "
     << w[0] << " J, the friction forces " << w[1] << " J";
  int kMax = -1;
  for (int k = 0; k < contact.numNodes(); ++k)
    if (contact.force()(k) > 0.0 && (kMax < 0 || contact.force()(k) > contact.force()(kMax))) kMax = k;
  if (kMax >= 0)
    os << "; largest force at contact node " << contact.nodes()[kMax] << " (" << contact.force()(kMax) << " N, "
       << contact.numActive() << " node(s) in contact)";
}

}  // namespace

std::string Simulation::diagnoseDivergence(const ExplicitLoop& loop, const EnergyGrowth& g, double h) const {
  if (!g.unbounded) return "";
  const ParameterList& P = *deck_.params;
  std::ostringstream os;
  os << "the bodies' energy (kinetic + strain) grows without bound";
  if (std::isfinite(g.e1))
    os << ", from " << g.e0 << " to " << g.e1 << " J over the last " << g.records << " records (t = " << g.t0 << " to "
       << g.t1 << " s, e-folding time " << g.efolding << " s)";
  else
    os << " (no longer finite)";
  const std::string source = std::isfinite(g.e1) ? g.source() : "the integrator";
  const SurfaceContact* contact = scene_->contact();
  os << ". It came from " << source;
  if (source == "contact work") {
    os << " (" << g.contactWork << " J over the rise";
    if (contact) describeContact(os, loop, *contact, fastestRotation(P) != 0.0);
    os << ")";
  } else if (source == "external work") {
    os << " (" << g.externalWork << " J over the rise)";
  } else if (std::isfinite(g.e1)) {
    os << " (no force's work fed it: contact work " << g.contactWork << " J, external work " << g.externalWork
       << " J over the rise, half-step energy changed by " << g.total << " J, balance error " << g.balance << ")";
  }
  if (!P.sublist("Run").get<bool>("Divergence step check")) {
    os << ". Whether the step matters was not checked ('Run->Divergence step check' = false)";
    return os.str();
  }
  if (rt_.size() > 1) {
    os << ". Whether the step matters was not checked (run on one MPI rank to check it)";
    return os.str();
  }
  const double tStop = loop.time(), tEnd = std::min(2.0 * tStop, numberOfSteps(P, deck_.origin) * h);
  const double t2 = rerunAtHalfStep(h, tEnd);
  if (std::isnan(t2)) {
    os << ". Whether the step matters could not be checked (the deck at h/2 did not set up)";
  } else if (t2 < 0) {
    os << ". At h/2 = " << 0.5 * h << " s the run passes t = " << tEnd << " s without diverging: the step "
       << "changes it, a numerical instability. Use 'Time->Time step' <= " << 0.5 * h << " s";
  } else {
    os << ". At h/2 = " << 0.5 * h << " s it diverges too (stopped at t = " << t2 << " s): the step does not "
       << "change it";
    if (source == "the integrator")
      os << ", and no force's work fed it: not classified";
    else
      os << ", a physical instability of the model"
         << (source == "contact work" ? " fed by contact (friction-fed when the friction forces' part dominates)" : "")
         << ", not a time-step problem: a smaller step does not help (see docs/user/divergence.md)";
  }
  return os.str();
}

double Simulation::rerunAtHalfStep(double h, double tEnd) const {
  Deck d = deck_;
  d.params = Teuchos::rcp(new ParameterList(*deck_.params));
  ParameterList& T = d.params->sublist("Time");
  T.set("Time step", 0.5 * h);
  T.set("End time", tEnd);
  T.set("End revolutions", 0.0);
  ParameterList& O = d.params->sublist("Output");
  O.set("Checkpoint every", 0);
  O.set("Checkpoint interval", 0.0);
  O.set("Fields every", 0);
  d.params->sublist("Run").set("Progress interval", 0.0);
  d.params->sublist("Run").set("Divergence step check", false);
  const std::string scratch = output_ + ".step-check.h5";
  Simulation check(d, rt_, scratch);
  double stopped = -1;
  try {
    check.setup();
  } catch (const Error&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  try {
    check.run();
  } catch (const Error&) {
    stopped = check.summary_.stopTime;
  }
  std::remove(scratch.c_str());
  return stopped;
}

}  // namespace epaphe
