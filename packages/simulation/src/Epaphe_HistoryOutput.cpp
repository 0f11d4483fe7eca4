#include "Epaphe_HistoryOutput.hpp"

namespace epaphe {

namespace {
constexpr int kChunk = 32;  // records recovered together (a fixed dgemm shape: see NodeRecovery)
}  // namespace

struct HistoryOutput::BodySeries {
  std::vector<DenseVector> Mt;  // M t_d: rigid translations through the mass matrix
  std::vector<double> pending;  // [q v] of the records not yet recovered, 2 n per record (kChunk at most)
  int pendingRecords = 0;
  std::vector<double> recovered;  // [u v] of a chunk, 2 kChunk columns of the watched rows
  std::vector<std::unique_ptr<io::Series>> disp, vel;
  std::unique_ptr<io::Series> gap, force, totalForce, momentum;
  std::vector<double> gapRec, forceRec;
};

HistoryOutput::HistoryOutput(io::Hdf5File& file, const std::vector<std::unique_ptr<SceneBody>>& bodies,
                             SurfaceContact* contact, const EnergyMonitor& monitor, bool fresh)
    : file_(file),
      bodies_(bodies),
      contact_(contact),
      monitor_(monitor),
      time_(file, "/time", {}),
      kinetic_(file, "/energy/kinetic", {}),
      strain_(file, "/energy/strain", {}),
      total_(file, "/energy/total", {}),
      work_(file, "/energy/contact_work", {}),
      external_(file, "/energy/external_work", {}),
      damping_(file, "/energy/damping", {}),
      balance_(file, "/energy/balance_error", {}) {
  if (std::any_of(bodies_.begin(), bodies_.end(), [](const auto& b) { return b->runUp != nullptr; }))
    drive_ = std::make_unique<io::Series>(file, "/energy/drive_work", std::vector<std::uint64_t>{});
  for (const auto& bp : bodies_) {
    const SceneBody& b = *bp;
    auto r = std::make_unique<BodySeries>();
    const int n = b.rom->size;
    const std::string g = "/bodies/" + b.name;
    if (fresh) {
      file.writeDoubles(g + "/frequencies/reduced", b.reducedFrequencies);
      file.writeDoubles(g + "/frequencies/full", b.fullFrequencies);
      file.writeDoubles(g + "/frequencies/fixed_interface", b.rom->modeFrequencies);
      file.setAttribute(g, "reduction", b.method);
      file.setAttribute(g, "reduced_dofs", static_cast<long long>(n));
    }
    if (!b.watched.empty()) {
      r->pending.assign(2 * static_cast<std::size_t>(kChunk) * n, 0.0);
      r->recovered.assign(2 * static_cast<std::size_t>(kChunk) * b.recoveryWatched.rows(), 0.0);
    }
    // Linear momentum p_d = t_d^T M v and rigid mass m = t_x^T M t_x (rebound velocity = p / m).
    for (int d = 0; d < 3; ++d) {
      const auto t = b.rom->rigidTranslation(d);
      const auto Mtd = b.rom->massTimes(t);
      DenseVector Mt("Mt", n);
      auto h2 = Kokkos::create_mirror_view(Mt);
      for (int i = 0; i < n; ++i) h2(i) = Mtd[i];
      Kokkos::deep_copy(Mt, h2);
      r->Mt.push_back(Mt);
      if (d == 0 && fresh) {
        double m = 0;
        for (int i = 0; i < n; ++i) m += t[i] * h2(i);
        file.setAttribute(g, "rigid_mass", m);
      }
    }
    r->momentum = std::make_unique<io::Series>(file, g + "/momentum", std::vector<std::uint64_t>{3});
    for (const auto& [setName, nodes] : b.watched) {
      if (fresh)
        file.writeInts(g + "/nodesets/" + setName + "/nodes", std::vector<long long>(nodes.begin(), nodes.end()));
      const std::uint64_t nn = nodes.size();
      r->disp.push_back(std::make_unique<io::Series>(file, g + "/nodesets/" + setName + "/displacement",
                                                     std::vector<std::uint64_t>{nn, 3}));
      r->vel.push_back(std::make_unique<io::Series>(file, g + "/nodesets/" + setName + "/velocity",
                                                    std::vector<std::uint64_t>{nn, 3}));
    }
    if (b.contactEnd > b.contactBegin) {
      const auto& cn = contact_->nodes();
      if (fresh)
        file.writeInts(g + "/contact/nodes",
                       std::vector<long long>(cn.begin() + b.contactBegin, cn.begin() + b.contactEnd));
      const std::uint64_t nc = static_cast<std::uint64_t>(b.contactEnd - b.contactBegin);
      r->gap = std::make_unique<io::Series>(file, g + "/contact/gap", std::vector<std::uint64_t>{nc});
      r->force = std::make_unique<io::Series>(file, g + "/contact/force", std::vector<std::uint64_t>{nc});
      r->totalForce = std::make_unique<io::Series>(file, g + "/contact/total_force", std::vector<std::uint64_t>{});
      r->gapRec.resize(nc);
      r->forceRec.resize(nc);
    }
    perBody_.push_back(std::move(r));
  }
}

HistoryOutput::~HistoryOutput() = default;

void HistoryOutput::recordHeat(const std::vector<int>& heated) {
  heated_ = heated;
  std::vector<std::string> names = {"friction_heat", "normal_work", "counterface_work"};
  for (int b : heated) names.push_back("heat/" + bodies_[static_cast<std::size_t>(b)]->name);
  names.push_back("heat/counterface");
  for (const std::string& n : names)
    heat_.push_back(std::make_unique<io::Series>(file_, "/energy/" + n, std::vector<std::uint64_t>{}));
}

std::vector<io::Series*> HistoryOutput::series() {
  std::vector<io::Series*> s = {&time_, &kinetic_, &strain_, &total_, &work_, &external_, &damping_, &balance_};
  if (drive_) s.push_back(drive_.get());
  for (const auto& h : heat_) s.push_back(h.get());
  for (const auto& r : perBody_) {
    s.push_back(r->momentum.get());
    for (std::size_t w = 0; w < r->disp.size(); ++w) {
      s.push_back(r->disp[w].get());
      s.push_back(r->vel[w].get());
    }
    for (io::Series* c : {r->gap.get(), r->force.get(), r->totalForce.get()})
      if (c != nullptr) s.push_back(c);
  }
  return s;
}

void HistoryOutput::afterCorrect(ExplicitLoop& loop) {
  if (!monitor_.measures(loop)) return;
  ScopedPhase phase(loop.cost(), "output");
  const double t = loop.time();
  if (contact_) {
    const auto f = contact_->force();
    forceAll_.assign(f.data(), f.data() + f.extent(0));
    contact_->setTime(t);
    contact_->measureGaps(loop.current(), loop.cost());
    const auto gp = contact_->gap();
    gapAll_.assign(gp.data(), gp.data() + gp.extent(0));
  }
  for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
    const SceneBody& b = *bodies_[ib];
    BodySeries& r = *perBody_[ib];
    const DenseVector& v = loop.velocity(ib);
    const double p[3] = {epaphe::dot(r.Mt[0], v), epaphe::dot(r.Mt[1], v), epaphe::dot(r.Mt[2], v)};
    r.momentum->append(p);
    if (!r.disp.empty()) {
      const DenseVector q = loop.part(loop.current(), ib);
      const std::size_t n = q.extent(0);
      double* dst = r.pending.data() + 2 * n * static_cast<std::size_t>(r.pendingRecords);
      std::copy(q.data(), q.data() + n, dst);
      std::copy(v.data(), v.data() + n, dst + n);
      if (++r.pendingRecords == kChunk) recover(ib);
    }
    if (b.contactEnd > b.contactBegin) {
      double tf = 0;
      for (std::size_t k = 0; k < r.forceRec.size(); ++k) {
        r.forceRec[k] = forceAll_[b.contactBegin + k];
        r.gapRec[k] = gapAll_[b.contactBegin + k];
        tf += r.forceRec[k];
      }
      r.gap->append(r.gapRec.data());
      r.force->append(r.forceRec.data());
      r.totalForce->append(&tf);
    }
  }
  const EnergySnapshot& e = monitor_.last();
  time_.append(&t);
  kinetic_.append(&e.kinetic);
  strain_.append(&e.strain);
  total_.append(&e.total);
  work_.append(&e.contactWork);
  external_.append(&e.externalWork);
  damping_.append(&e.damping);
  balance_.append(&e.balance);
  if (drive_) drive_->append(&e.driveWork);
  if (!heat_.empty()) {  // eq. 63's terms, and the heat's partition: each heated body's share, the rest
    const std::vector<double>& received = loop.accumulators().heatReceived;
    heat_[0]->append(&e.frictionHeat);
    heat_[1]->append(&e.normalWork);
    heat_[2]->append(&e.counterfaceWork);
    double rest = e.frictionHeat + loop.accumulators().coatingHeat;  // the heat made: friction's and the coating's
    for (std::size_t i = 0; i < heated_.size(); ++i) {
      const double q = received[static_cast<std::size_t>(heated_[i])];
      heat_[3 + i]->append(&q);
      rest -= q;
    }
    heat_.back()->append(&rest);
  }
}

void HistoryOutput::recover(std::size_t ib) {
  BodySeries& r = *perBody_[ib];
  if (r.pendingRecords == 0) return;
  const NodeRecovery& R = bodies_[ib]->recoveryWatched;
  const std::size_t n = static_cast<std::size_t>(bodies_[ib]->rom->size), m = R.rows();
  // a partial chunk (at a checkpoint or the end) is padded with zeros: the call's shape stays fixed
  std::fill(r.pending.begin() + 2 * n * static_cast<std::size_t>(r.pendingRecords), r.pending.end(), 0.0);
  R.applyColumns(r.pending.data(), 2 * kChunk, r.recovered.data());
  for (int j = 0; j < r.pendingRecords; ++j) {
    const double* u = r.recovered.data() + 2 * m * static_cast<std::size_t>(j);
    std::size_t off = 0;
    for (std::size_t w = 0; w < r.disp.size(); ++w) {
      r.disp[w]->append(u + off);
      r.vel[w]->append(u + m + off);
      off += r.disp[w]->recordSize();
    }
  }
  r.pendingRecords = 0;
}

void HistoryOutput::completeRecords() {
  for (std::size_t ib = 0; ib < perBody_.size(); ++ib) recover(ib);
}

void HistoryOutput::failed(ExplicitLoop&, const std::string& why) {
  completeRecords();
  file_.setAttribute("/", "status", "stopped: " + why);
  file_.flush();
}

}  // namespace epaphe
