// Progress for library callers: one begin per stage fill() runs, numbered by its plan; stage
// fractions from 0 to 1 and an overall fraction that never goes back and ends at 1; at most
// kMaxReportsPerStage reports a stage; calls never concurrent; cancelling from any stage; the
// same announcements for any thread count. The plan itself (detail::JobProgress) is tested
// directly for what fill() cannot show: parts of a stage, throttling, out-of-order reports.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <vector>

#include "core/job_progress.hpp"
#include "test_util.hpp"

using namespace tpmsfill;

namespace {

// Records every call, with no lock of its own (the contract says it needs none) but a check
// that no two calls overlap.
class Recorder : public Progress {
 public:
  struct Stage {
    std::string name;
    int index = 0, count = 0;
    std::vector<double> fractions, overall;
  };
  std::vector<Stage> stages;       ///< begin(StageInfo) with no step, with its reports
  std::vector<std::string> parts;  ///< "stage/step" of begins with a step
  std::string cancel_in;           ///< the stage whose first report says stop
  std::string cancel_mid;          ///< the stage whose first report strictly inside (0, 1) does
  bool cancelled = false;
  int calls_after_cancel = 0;
  int orphan_reports = 0;  ///< reports before any stage began
  bool overlapped = false;

  void begin(const StageInfo& s) override {
    Enter in(*this);
    if (!s.step.empty()) {
      parts.push_back(std::string(s.name) + "/" + std::string(s.step));
      return;
    }
    stages.push_back({std::string(s.name), s.index, s.count, {}, {}});
  }
  bool report(double fraction, double all) override {
    Enter in(*this);
    if (stages.empty()) return ++orphan_reports, true;
    stages.back().fractions.push_back(fraction);
    stages.back().overall.push_back(all);
    if (stages.back().name == cancel_in) cancelled = true;
    if (stages.back().name == cancel_mid && fraction > 0 && fraction < 1) cancelled = true;
    return !cancelled;
  }
  std::vector<std::string> names() const {
    std::vector<std::string> n;
    for (const Stage& s : stages) n.push_back(s.name);
    return n;
  }

 private:
  struct Enter {
    Recorder& r;
    explicit Enter(Recorder& rec) : r(rec) {
      if (r.active_.fetch_add(1) != 0) r.overlapped = true;
      if (r.cancelled) ++r.calls_after_cancel;
    }
    ~Enter() { r.active_.fetch_sub(1); }
  };
  std::atomic<int> active_{0};
};

FillOptions small_job() {
  FillOptions o;
  o.grid.voxel_size = 0.2;
  o.design.cell = {3, 3, 3};
  return o;
}

const std::vector<std::string> kClosedStages{"review",         "spatial",  "classify",
                                             "band",           "distance", "compose",
                                             "marching cubes", "islands",  "validate"};
// Auto inside on an open box: the rows disagree, so it cleans (caps the hole) and classifies
// again.
const std::vector<std::string> kOpenStages{"review",  "spatial",        "classify", "clean",
                                           "spatial", "classify",       "band",     "distance",
                                           "compose", "marching cubes", "islands",  "validate"};

void expect_well_formed(const Recorder& r, const FillReport& report,
                        const std::vector<std::string>& expected) {
  EXPECT_EQ(r.names(), expected);
  ASSERT_EQ(r.stages.size(), report.stages.size());
  for (std::size_t i = 0; i < r.stages.size(); ++i)
    EXPECT_EQ(r.stages[i].name, report.stages[i].name);  // the report's table, same order
  EXPECT_FALSE(r.overlapped) << "two calls at once";
  EXPECT_EQ(r.orphan_reports, 0);
  double last_overall = 0;
  for (std::size_t i = 0; i < r.stages.size(); ++i) {
    const Recorder::Stage& s = r.stages[i];
    SCOPED_TRACE(s.name + " #" + std::to_string(s.index));
    EXPECT_GE(s.index, 1);
    EXPECT_LE(s.index, s.count);
    if (i) {
      EXPECT_GT(s.index, r.stages[i - 1].index);
      EXPECT_EQ(s.count, r.stages[0].count);
    }
    ASSERT_FALSE(s.fractions.empty());
    EXPECT_LE(s.fractions.size(), static_cast<std::size_t>(kMaxReportsPerStage));
    EXPECT_EQ(s.fractions.front(), 0.0);
    EXPECT_EQ(s.fractions.back(), 1.0);
    for (std::size_t k = 0; k < s.fractions.size(); ++k) {
      if (k) {
        EXPECT_GE(s.fractions[k], s.fractions[k - 1]) << "stage fraction went back";
      }
      EXPECT_GE(s.overall[k], last_overall) << "overall went back at report " << k;
      EXPECT_LE(s.overall[k], 1.0);
      last_overall = s.overall[k];
    }
  }
  EXPECT_EQ(last_overall, 1.0);
}

}  // namespace

TEST(Progress, ClosedMeshAnnouncesEveryStageItRuns) {
  // Auto classifies once; the planned clean and second pass are skipped, never announced.
  Recorder r;
  FillOptions o = small_job();
  o.progress = &r;
  const FillResult a = fill(test::make_box({0, 0, 0}, {12, 12, 12}), o);
  expect_well_formed(r, a.report, kClosedStages);
  EXPECT_EQ(r.stages.front().count, 12);  // the plan held the possible second pass
  EXPECT_EQ(r.stages[3].index, 7);        // band: the three skipped stages are numbered
  EXPECT_TRUE(r.parts.empty());           // fill's stage functions repeat the stages' names
}

TEST(Progress, OpenMeshClassifiesTwiceWithoutRestarting) {
  Recorder r;
  FillOptions o = small_job();
  o.progress = &r;
  const FillResult b = fill(test::make_box_with_hole({0, 0, 0}, {12, 12, 12}), o);
  expect_well_formed(r, b.report, kOpenStages);
  EXPECT_EQ(r.stages.back().index, r.stages.back().count);  // every planned stage ran
  // The second classification starts where the first left the job, not at 0.
  EXPECT_GT(r.stages[5].overall.front(), r.stages[2].overall.back());
}

TEST(Progress, OptionalStagesJoinThePlan) {
  // Depth grading, measuring and an explicit winding rule change the plan.
  Recorder r;
  FillOptions o = small_job();
  o.progress = &r;
  o.measure = true;
  o.inside = InsideRule::Winding;
  o.design.grading.push_back(
      {Graded::Porosity, {.shape = RampShape::Depth, .start = 0.5, .end = 0.7}});
  const FillResult c = fill(test::make_box({0, 0, 0}, {12, 12, 12}), o);
  expect_well_formed(r, c.report,
                     {"review", "clean", "spatial", "classify", "depth", "band", "distance",
                      "compose", "marching cubes", "islands", "measure", "validate"});
  EXPECT_EQ(r.stages.front().count, 12);
}

TEST(Progress, TheSimplePairStillWorks) {
  // A Progress written before the plan existed: one begin per stage, fractions in [0, 1].
  struct Simple : Progress {
    std::vector<std::string> begins;
    int reports = 0;
    bool in_range = true;
    void begin(std::string_view s) override { begins.emplace_back(s); }
    bool report(double f) override {
      ++reports;
      in_range = in_range && f >= 0 && f <= 1;
      return true;
    }
  } simple;
  FillOptions o = small_job();
  o.progress = &simple;
  fill(test::make_box({0, 0, 0}, {12, 12, 12}), o);
  EXPECT_EQ(simple.begins, kClosedStages);
  EXPECT_GE(simple.reports, 2 * static_cast<int>(kClosedStages.size()));
  EXPECT_TRUE(simple.in_range);
}

TEST(Progress, CancellingInAnyStageThrowsAndStopsCalling) {
  // Every stage, including those that report nothing of their own (spatial, band, islands),
  // can be cancelled from its first report; nothing later is announced or returned.
  for (const std::string& stage : kOpenStages) {
    SCOPED_TRACE(stage);
    Recorder r;
    r.cancel_in = stage;
    FillOptions o = small_job();
    o.progress = &r;
    EXPECT_THROW(fill(test::make_box_with_hole({0, 0, 0}, {12, 12, 12}), o), Cancelled);
    ASSERT_FALSE(r.stages.empty());
    EXPECT_EQ(r.stages.back().name, stage);
    EXPECT_EQ(r.stages.back().fractions.size(), 1u);  // the first report said stop
    EXPECT_EQ(r.calls_after_cancel, 0);
  }
}

TEST(Progress, CancellingMidStageStopsTheWorkers) {
  // The stages that report their own fractions stop within one: a worker's report hears
  // stop, and the other workers' reports no longer reach the caller.
  for (const char* stage : {"classify", "distance", "compose", "marching cubes", "validate"}) {
    SCOPED_TRACE(stage);
    Recorder r;
    r.cancel_mid = stage;
    FillOptions o = small_job();
    o.progress = &r;
    EXPECT_THROW(fill(test::make_box({0, 0, 0}, {12, 12, 12}), o), Cancelled);
    ASSERT_FALSE(r.stages.empty());
    EXPECT_EQ(r.stages.back().name, stage);
    EXPECT_GE(r.stages.back().fractions.size(), 2u);
    EXPECT_LT(r.stages.back().fractions.back(), 1.0);
    EXPECT_EQ(r.calls_after_cancel, 0);
  }
}

TEST(Progress, AnnouncementsDoNotDependOnTheThreadCount) {
  auto run = [](std::size_t threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Recorder r;
    FillOptions o = small_job();
    o.progress = &r;
    const FillResult result = fill(test::make_box_with_hole({0, 0, 0}, {12, 12, 12}), o);
    expect_well_formed(r, result.report, kOpenStages);
    std::vector<std::string> names;
    for (const auto& b : r.stages) names.push_back(b.name + "#" + std::to_string(b.index));
    return names;
  };
  const std::vector<std::string> one = run(1);
  EXPECT_EQ(one.size(), kOpenStages.size());
  EXPECT_EQ(one, run(8));
}

TEST(Progress, JobPlanNumbersCreditsThrottlesAndForwardsParts) {
  Recorder r;
  detail::JobProgress job(&r, {{"a", 1}, {"b", 1}, {"c", 2}, {"d", 1}});
  Progress* p = job.get();
  ASSERT_EQ(p, &job);
  job.begin_stage("a");
  p->begin("a");  // a stage function repeating the stage's name: not announced again
  for (int i = 0; i <= 10000; ++i) EXPECT_TRUE(p->report(i / 10000.0));
  EXPECT_TRUE(p->report(0.5));  // out of order (another thread was faster): not forwarded
  job.end_stage();
  job.begin_stage("c");  // b was not needed: credited
  p->begin("edges");     // a part of c
  EXPECT_TRUE(p->report(0.5));
  job.end_stage();
  job.begin_stage("d");
  job.end_stage();
  job.finish();

  ASSERT_EQ(r.names(), (std::vector<std::string>{"a", "c", "d"}));
  EXPECT_EQ(r.stages[1].index, 3);
  EXPECT_EQ(r.stages[1].count, 4);
  EXPECT_EQ(r.parts, std::vector<std::string>{"c/edges"});
  EXPECT_EQ(r.stages[0].fractions.size(), 101u);  // 0, each whole percent, 1
  EXPECT_DOUBLE_EQ(r.stages[0].overall.back(), 0.2);
  EXPECT_DOUBLE_EQ(r.stages[1].overall.front(), 0.4);  // a and the skipped b
  EXPECT_DOUBLE_EQ(r.stages[1].overall[1], 0.6);       // half of c's 2 of 5
  EXPECT_EQ(r.stages[1].fractions, (std::vector<double>{0, 0.5, 1}));
  EXPECT_EQ(r.stages[2].overall.back(), 1.0);
  EXPECT_EQ(r.stages[2].fractions.size(), 2u);  // finish() had nothing left to say

  // Without a caller there is nothing to report to, and nothing is called.
  detail::JobProgress none(nullptr, {{"a", 1}});
  EXPECT_EQ(none.get(), nullptr);
  none.begin_stage("a");
  none.end_stage();
  none.finish();
}

TEST(Progress, JobPlanCancelsAtAStageStart) {
  Recorder r;
  r.cancel_in = "b";
  detail::JobProgress job(&r, {{"a", 1}, {"b", 1}, {"c", 1}});
  job.begin_stage("a");
  job.end_stage();
  EXPECT_THROW(job.begin_stage("b"), Cancelled);
  EXPECT_FALSE(job.get()->report(0.5));  // a worker still running hears stop
  EXPECT_THROW(job.end_stage(), Cancelled);
  EXPECT_THROW(job.begin_stage("c"), Cancelled);
  job.finish();
  EXPECT_EQ(r.names(), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(r.calls_after_cancel, 0);
}
