#pragma once
// SurfaceContact and its run guards (Epaphe_ContactGuards.hpp) as the explicit loop's contact
// (ContactCorrector, Epaphe_ContactCorrector.hpp): each step the correction of q* at t_{n+1}, then
// the guards' check of the contact nodes' motion over the step. Every call forwards one whole-step
// call; the loop sees nothing of the nodes.
#include "Epaphe_ContactCorrector.hpp"
#include "Epaphe_ContactGuards.hpp"
#include "Epaphe_SurfaceContact.hpp"

namespace epaphe {

/// SurfaceContact and its run guards as the explicit loop's ContactCorrector (see the file's opening comment).
class GuardedContact final : public ContactCorrector {
public:
  /// Both outlive this object.
  GuardedContact(SurfaceContact& contact, const ContactGuards& guards) : contact_(contact), guards_(guards) {}

  void correct(double t, const DenseVector& qPredicted, const DenseVector& qCurrent, CostSplit& cost) override {
    contact_.setTime(t);
    contact_.correct(qPredicted, qCurrent, cost);
  }
  std::string checkStep(const DenseVector& qNext, const DenseVector& qCurrent, double t, double h) const override {
    return guards_.checkStep(contact_, qNext, qCurrent, t, h);
  }
  bool largeMotionAllowed() const override { return guards_.options().allowLargeMotion; }
  double workIncrement(const DenseVector& qNext, const DenseVector& qPrev) const override {
    return contact_.workIncrement(qNext, qPrev);
  }
  void generalizedForce(const DenseVector& g) const override { contact_.generalizedForce(g); }
  double totalForce() const override { return contact_.totalForce(); }
  int numActive() const override { return contact_.numActive(); }
  Kokkos::View<double*>::HostMirror forces() const override { return contact_.force(); }
  void setReferencePositions(const std::vector<double>& X) override { contact_.setReferencePositions(X); }

  /// The contact operator.
  SurfaceContact& contact() const { return contact_; }
  /// The run guards.
  const ContactGuards& guards() const { return guards_; }

private:
  SurfaceContact& contact_;
  const ContactGuards& guards_;
};

}  // namespace epaphe
