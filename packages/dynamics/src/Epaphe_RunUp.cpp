#include "Epaphe_RunUp.hpp"

#include "Epaphe_Error.hpp"

#include <cmath>

namespace epaphe {

long long RunUpModel::level(double t) const {
  const double w = law.speed(t) / maxSpeed;
  return std::llround(w * w / xiStep);
}

std::vector<double> RunUpModel::stiffnessAt(long long l) const {
  const double xi = xiOf(l);
  std::vector<double> K = stiffness.front();
  double p = 1;
  for (std::size_t k = 1; k < stiffness.size(); ++k) {  // K_r(xi) = sum_k xi^k R_k
    p *= xi;
    for (std::size_t i = 0; i < K.size(); ++i) K[i] += p * stiffness[k][i];
  }
  return K;
}

std::vector<double> RunUpModel::positionsAt(long long l) const {
  const double xi = xiOf(l);
  std::vector<double> x = restX;
  double p = 1;
  for (std::size_t k = 0; k < growth.size(); ++k) {  // X + u_s(xi), u_s = sum_k xi^k g_k
    for (std::size_t i = 0; i < x.size(); ++i) x[i] += p * growth[k][i];
    p *= xi;
  }
  return x;
}

RunUp::RunUp(std::vector<Driven> driven, ContactCorrector* contact, std::vector<double> contactX)
    : driven_(std::move(driven)), contact_(contact), contactX_(std::move(contactX)) {
  level_.assign(driven_.size(), 0);
  K_.resize(driven_.size());
  for (std::size_t i = 0; i < driven_.size(); ++i) {
    EPAPHE_REQUIRE(driven_[i].integrator && driven_[i].model && !driven_[i].model->stiffness.empty(),
                   "RunUp: driven body " << driven_[i].body << " has no integrator or no stiffness polynomial");
    apply(i, driven_[i].model->level(0.0));
  }
}

void RunUp::apply(std::size_t i, long long level) {
  const RunUpModel& m = *driven_[i].model;
  level_[i] = level;
  K_[i] = m.stiffnessAt(level);
  driven_[i].integrator->setStiffness(K_[i]);
  if (contact_ && !m.restX.empty()) {
    const std::vector<double> x = m.positionsAt(level);
    std::copy(x.begin(), x.end(), contactX_.begin() + 3 * static_cast<std::ptrdiff_t>(m.contactBegin));
    contact_->setReferencePositions(contactX_);
  }
  ++refreshes_;
}

void RunUp::beginRun(ExplicitLoop& loop) {
  const long long last = std::max(loop.firstStep() - 1, 0LL);
  for (std::size_t i = 0; i < driven_.size(); ++i) {
    const long long l = driven_[i].model->level(static_cast<double>(last) * loop.timeStep());
    if (l != level_[i]) apply(i, l);
  }
}

void RunUp::beginStep(ExplicitLoop& loop) {
  for (std::size_t i = 0; i < driven_.size(); ++i) {
    const long long l = driven_[i].model->level(loop.time());
    if (l == level_[i]) continue;
    const std::vector<double> before = K_[i];
    apply(i, l);
    // W_drive += 1/2 q_{n-1}^T (K_l' - K_l) q_n
    const std::size_t b = driven_[i].body;
    const DenseVector qp = loop.part(loop.previous(), b), qc = loop.part(loop.current(), b);
    const int n = static_cast<int>(qc.extent(0));
    double w = 0;
    for (int c = 0; c < n; ++c) {
      double col = 0;
      for (int r = 0; r < n; ++r) {
        const std::size_t k = static_cast<std::size_t>(c) * n + r;
        col += qp(r) * (K_[i][k] - before[k]);
      }
      w += col * qc(c);
    }
    loop.accumulators().driveWork[b] += 0.5 * w;
  }
}

}  // namespace epaphe
