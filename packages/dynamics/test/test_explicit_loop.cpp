// The explicit loop as a component (Epaphe_ExplicitLoop.hpp): hook order, observers' control
// (stop requests, failures), a restart from a saved state that continues bit for bit, and the
// energy monitor's balance and refusals on a damped oscillator.
#include "Epaphe_EnergyMonitor.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_RunControl.hpp"
#include "TestModels.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

namespace epaphe {
namespace {

/// Logs the hooks it sees, "name:step".
class HookLog : public LoopObserver {
public:
  std::vector<std::string> log;
  void beginRun(ExplicitLoop& l) override { add("beginRun", l.step()); }
  void beginStep(ExplicitLoop& l) override { add("beginStep", l.step()); }
  void afterPredict(ExplicitLoop& l) override { add("afterPredict", l.step()); }
  void afterCorrect(ExplicitLoop& l) override { add("afterCorrect", l.step()); }
  void endStep(ExplicitLoop& l) override { add("endStep", l.stepsDone()); }
  void endRun(ExplicitLoop& l) override { add("endRun", l.stepsDone()); }
  void failed(ExplicitLoop&, const std::string& why) override { log.push_back("failed:" + why); }

private:
  void add(const char* hook, long long n) { log.push_back(std::string(hook) + ":" + std::to_string(n)); }
};

/// One oscillator (m = 2 kg, k = 800 N/m), released from x0 = 1 mm with v = 0.
struct Scene {
  ReducedModel model = test::oscillator(2.0, 800.0);
  double h = 1e-3;
  CentralDifference cd;
  CostSplit cost;
  std::ostringstream out;
  explicit Scene(DampingOptions damping = {}) : cd(model, h, damping) {}
  ExplicitLoop loop(long long steps) {
    ExplicitLoop l({{"oscillator", &cd, 0, 3}}, h, steps, nullptr, cost, out);
    const double omega2 = 800.0 / 2.0;
    auto q = Kokkos::create_mirror_view(l.current());
    q(0) = 1e-3;
    Kokkos::deep_copy(l.current(), q);
    q(0) = 1e-3 * (1 - 0.5 * h * h * omega2);
    Kokkos::deep_copy(l.previous(), q);
    return l;
  }
};

std::vector<double> host(const DenseVector& v) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  return std::vector<double>(h.data(), h.data() + h.extent(0));
}

TEST(ExplicitLoop, HooksRunInOrderAroundEveryStep) {
  Scene s;
  auto loop = s.loop(2);
  HookLog hooks;
  loop.addObserver(&hooks);
  EXPECT_TRUE(loop.run());
  const std::vector<std::string> expected = {"beginRun:0", "beginStep:0", "afterPredict:0", "afterCorrect:0",
                                             "endStep:1",  "beginStep:1", "afterPredict:1", "afterCorrect:1",
                                             "endStep:2",  "endRun:2"};
  EXPECT_EQ(hooks.log, expected);
  EXPECT_EQ(loop.stepsDone(), 2);
  EXPECT_FALSE(loop.advance());  // finished: no further step
}

TEST(ExplicitLoop, AStopRequestEndsTheRunAfterItsStepAndARestartContinuesBitForBit) {
  Scene a;
  auto whole = a.loop(40);
  EXPECT_TRUE(whole.run());

  Scene b;
  auto first = b.loop(40);
  StopControl stop(17, "continue later");
  first.addObserver(&stop);
  EXPECT_FALSE(first.run());
  EXPECT_EQ(first.stepsDone(), 17);
  EXPECT_NE(first.stopReason().find("stopped after 17 steps"), std::string::npos) << first.stopReason();
  EXPECT_NE(first.stopReason().find("continue later"), std::string::npos);

  // A second loop started from the first's state at step 17, as a restart from a checkpoint.
  Scene c;
  auto second = c.loop(40);
  second.setFirstStep(first.stepsDone());
  Kokkos::deep_copy(second.previous(), first.previous());
  Kokkos::deep_copy(second.current(), first.current());
  EXPECT_TRUE(second.run());
  EXPECT_EQ(host(second.current()), host(whole.current()));
  EXPECT_EQ(host(second.previous()), host(whole.previous()));
}

TEST(ExplicitLoop, AFailureReachesEveryObserverThenThrows) {
  struct Failing : LoopObserver {
    void afterCorrect(ExplicitLoop& l) override {
      if (l.step() == 3) l.fail("step 3 is wrong");
    }
  } failing;
  Scene s;
  auto loop = s.loop(10);
  HookLog hooks;
  loop.addObserver(&failing);
  loop.addObserver(&hooks);
  EXPECT_THROW(loop.run(), Error);
  EXPECT_EQ(hooks.log.back(), "failed:step 3 is wrong");
}

TEST(EnergyMonitor, BalancesADampedOscillatorAndRefusesATightTolerance) {
  DampingOptions damping;
  damping.type = DampingType::Rayleigh;
  damping.alpha = 5.0;  // D = alpha M: xi = alpha / (2 omega) = 0.125
  {
    Scene s(damping);
    auto loop = s.loop(500);
    EnergyMonitor monitor(loop, {10, 1e-10, 0.0});
    loop.addObserver(&monitor);
    EXPECT_TRUE(loop.run());
    const EnergySnapshot& e = monitor.last();
    EXPECT_EQ(e.step, 499);                 // the last step is always measured
    EXPECT_GT(e.damping, 0.5 * e.initial);  // most of the energy is dissipated over 500 ms...
    EXPECT_LT(std::abs(e.balance), 1e-12);  // ...and accounted for
    EXPECT_LT(loop.accumulators().maxBalanceError, 1e-12);
  }
  {  // the same run with a wrong external work (1e-6 J added at step 100) is stopped
    Scene s(damping);
    auto loop = s.loop(500);
    EnergyMonitor monitor(loop, {10, 1e-10, 0.0});
    loop.addObserver(&monitor);
    struct Tamper : LoopObserver {
      void afterPredict(ExplicitLoop& l) override {
        if (l.step() == 100) l.accumulators().externalWork[0] += 1e-6;
      }
    } tamper;
    loop.addObserver(&tamper);
    try {
      loop.run();
      ADD_FAILURE() << "a wrong balance was not refused";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("energy balance error"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("Energy balance tolerance"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace epaphe
