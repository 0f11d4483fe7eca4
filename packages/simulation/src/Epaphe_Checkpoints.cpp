#include "Epaphe_Checkpoints.hpp"

#include "Epaphe_Error.hpp"

#include <algorithm>

namespace epaphe {

namespace {

constexpr long long kRecordBuffer = 1024, kFrameBuffer = 16;  // the series' buffers (records)

std::vector<double> hostCopy(const DenseVector& v) {
  auto hv = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  return std::vector<double>(hv.data(), hv.data() + hv.extent(0));
}

}  // namespace

Checkpoints::Checkpoints(io::Hdf5File& file, const ExplicitLoop& loop, SurfaceContact* contact, HistoryOutput& history,
                         FieldOutput* fields, const CheckpointOptions& options, const std::vector<io::Series*>& more)
    : file_(file),
      contact_(contact),
      history_(history),
      fields_(fields),
      opt_(options),
      series_(history.series()),
      accumulatorNames_(LoopAccumulators::names(loop.bodies(), loop.accumulators().heatTerm())) {
  if (fields_)
    for (io::Series* s : fields_->series()) series_.push_back(s);
  series_.insert(series_.end(), more.begin(), more.end());
  for (const io::Series* s : series_) seriesPaths_ += s->path() + "\n";
}

void Checkpoints::write(const ExplicitLoop& loop, long long nextStep) {
  Stopwatch w;
  history_.completeRecords();
  // First the buffered records, flushed: a kill before the checkpoint's own data is flushed then
  // leaves series at least as long as the previous checkpoint's lengths (a restart cuts them).
  file_.flush();
  const std::string c = "/checkpoint/" + std::to_string(slot_);
  if (!file_.exists(c + "/series_paths")) {
    file_.writeString(c + "/series_paths", seriesPaths_);
    std::string names;
    for (const auto& a : accumulatorNames_) names += (names.empty() ? "" : ",") + a;
    file_.writeDoubles(c + "/accumulators", std::vector<double>(accumulatorNames_.size(), 0.0));
    file_.setAttribute(c + "/accumulators", "names", names);
    file_.setAttribute(c, "counters", "step (the next to run), records, frames");
  }
  const long long records = history_.records(), frames = fields_ ? fields_->frames() : 0;
  file_.writeInts(c + "/counters", std::vector<long long>{nextStep, records, frames});
  file_.writeDoubles(c + "/q_prev", hostCopy(loop.previous()));
  file_.writeDoubles(c + "/q", hostCopy(loop.current()));
  file_.writeDoubles(c + "/accumulators", loop.accumulators().values(static_cast<double>(nextStep) * loop.timeStep()));
  if (SurfaceContact* contact = contact_) {
    const auto uv = contact->warmStarts();
    file_.writeDoubles(c + "/warm_start",
                       {uv.size() / (2 * contact->numNodes()), static_cast<std::uint64_t>(contact->numNodes()), 2},
                       uv.data());
    file_.writeDoubles(c + "/detection_state", contact->detectionState());
    if (contact->coating()) file_.writeDoubles(c + "/coating_state", contact->coatingState());
    contact->resetWarmStarts();  // as a restart from here will: friction starts anew
  }
  if (heat_) file_.writeDoubles(c + "/thermal_state", heat_->state());
  std::vector<double> residual;  // the massless boundaries' residual forces (CentralDifference::residualForces)
  const std::vector<double> q = hostCopy(loop.current()), qPrev = hostCopy(loop.previous());
  for (const LoopBody& b : loop.bodies()) {
    const std::vector<double> z = b.integrator->residualForces(q.data() + b.offset, qPrev.data() + b.offset);
    residual.insert(residual.end(), z.begin(), z.end());
  }
  if (!residual.empty()) file_.writeDoubles(c + "/residual_forces", residual);
  std::vector<long long> lengths;
  for (const io::Series* s : series_) lengths.push_back(static_cast<long long>(s->size()));
  file_.writeInts(c + "/series_lengths", lengths);
  file_.flush();  // H5Fflush
  file_.writeInts("/checkpoint/current", std::vector<long long>{slot_, nextStep});
  file_.flush();
  slot_ = 1 - slot_;
  recordsAt_ = records;
  framesAt_ = frames;
  ++count_;
  seconds_ += w.seconds();
}

long long Checkpoints::restore(ExplicitLoop& loop, const std::string& what) {
  // The last complete checkpoint; the series cut to its records; the next checkpoint goes to the
  // other slot.
  const auto current = file_.readInts("/checkpoint/current");
  EPAPHE_REQUIRE(current.size() == 2 && (current[0] == 0 || current[0] == 1),
                 what << ": /checkpoint/current is damaged or from another run");
  const std::string c = "/checkpoint/" + std::to_string(current[0]);
  slot_ = 1 - static_cast<int>(current[0]);
  const auto counters = file_.readInts(c + "/counters");
  EPAPHE_REQUIRE(counters.size() == 3 && counters[0] == current[1] && counters[0] <= loop.numSteps(),
                 what << ": " << c << "/counters is damaged or from another run");
  EPAPHE_REQUIRE(file_.readString(c + "/series_paths") == seriesPaths_,
                 what << ": its series are not those of this deck's run; run the deck anew");
  const auto lengths = file_.readInts(c + "/series_lengths");
  EPAPHE_REQUIRE(lengths.size() == series_.size(), what << ": " << c << "/series_lengths has " << lengths.size()
                                                        << " entries, " << series_.size() << " expected");
  for (std::size_t i = 0; i < series_.size(); ++i) series_[i]->truncate(static_cast<std::size_t>(lengths[i]));
  loop.setFirstStep(counters[0]);
  recordsAt_ = counters[1];  // the series' lengths now
  framesAt_ = counters[2];
  auto load = [&](const DenseVector& v, const std::string& path) {
    const auto values = file_.readDoubles(path);
    EPAPHE_REQUIRE(values.size() == v.extent(0),
                   what << ": " << path << " has " << values.size() << " values, the system " << v.extent(0));
    auto hv = Kokkos::create_mirror_view(v);
    std::copy(values.begin(), values.end(), hv.data());
    Kokkos::deep_copy(v, hv);
  };
  load(loop.previous(), c + "/q_prev");
  load(loop.current(), c + "/q");
  loop.accumulators().restore(file_.readDoubles(c + "/accumulators"), what + ": " + c + "/accumulators");
  if (SurfaceContact* contact = contact_) {
    contact->setWarmStarts(file_.readDoubles(c + "/warm_start"));
    if (file_.exists(c + "/detection_state"))  // (a checkpoint without it: every node projects)
      contact->setDetectionState(file_.readDoubles(c + "/detection_state"));
    if (contact->coating()) {
      EPAPHE_REQUIRE(file_.exists(c + "/coating_state"),
                     what << ": " << c << " has no coating state; run the deck anew");
      contact->setCoatingState(file_.readDoubles(c + "/coating_state"));
    }
  }
  std::size_t count = 0;
  for (const LoopBody& b : loop.bodies()) count += b.integrator->residualForceCount();
  if (count > 0) {
    const std::string path = c + "/residual_forces";
    const std::vector<double> z = file_.exists(path) ? file_.readDoubles(path) : std::vector<double>{};
    EPAPHE_REQUIRE(z.size() == count, what << ": " << path << " holds " << z.size()
                                           << " values where the massless boundaries' residual forces are " << count
                                           << "; run the deck anew");
    const std::vector<double> q = hostCopy(loop.current()), qPrev = hostCopy(loop.previous());
    std::size_t at = 0;
    for (const LoopBody& b : loop.bodies()) {
      b.integrator->restoreResidualForces(q.data() + b.offset, qPrev.data() + b.offset, z.data() + at);
      at += b.integrator->residualForceCount();
    }
  }
  if (heat_) {
    EPAPHE_REQUIRE(file_.exists(c + "/thermal_state"), what << ": " << c << " has no thermal state; run the deck anew");
    heat_->setState(file_.readDoubles(c + "/thermal_state"), what + ": " + c + "/thermal_state");
  }
  file_.flush();
  return counters[0];
}

void Checkpoints::endStep(ExplicitLoop& loop) {
  const long long done = loop.stepsDone();
  if (done >= loop.numSteps()) return;
  const long long records = history_.records(), frames = fields_ ? fields_->frames() : 0;
  if (loop.stopRequested() || (opt_.every > 0 && done % opt_.every == 0) || records - recordsAt_ >= kRecordBuffer - 1 ||
      frames - framesAt_ >= kFrameBuffer - 1 ||
      (opt_.interval > 0 && (loop.step() & 63) == 0 && since_.seconds() > opt_.interval)) {
    ScopedPhase phase(loop.cost(), "checkpoint");
    write(loop, done);
    since_.restart();
  }
}

}  // namespace epaphe
