// Progress for library callers: one begin per stage of fill's plan, numbered, an overall
// fraction that never goes back and ends at 1, cancellation, and the same announcements for
// any thread count.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <mutex>
#include <string>
#include <tpmsfill/error.hpp>
#include <tpmsfill/fill.hpp>
#include <vector>

#include "test_util.hpp"

using namespace tpmsfill;

namespace {

class Recorder : public Progress {
 public:
  struct Begin {
    std::string name;
    int index, count;
  };
  std::vector<Begin> begins;
  std::vector<double> overall;
  std::vector<double> stage;
  long cancel_after = -1;  ///< report() calls before cancelling (-1: never)

  void begin(const StageInfo& s) override {
    begins.push_back({std::string(s.name), s.index, s.count});
  }
  bool report(double fraction, double all) override {
    std::lock_guard lock(mutex_);
    stage.push_back(fraction);
    overall.push_back(all);
    return cancel_after < 0 || static_cast<long>(overall.size()) <= cancel_after;
  }

 private:
  std::mutex mutex_;
};

FillOptions small_job() {
  FillOptions o;
  o.grid.voxel_size = 0.2;
  o.design.cell = {3, 3, 3};
  return o;
}

void expect_well_formed(const Recorder& r, const FillReport& report) {
  // One begin per stage of the report's table, in the same order, numbered upwards.
  ASSERT_EQ(r.begins.size(), report.stages.size());
  for (std::size_t i = 0; i < r.begins.size(); ++i) {
    EXPECT_EQ(r.begins[i].name, report.stages[i].name);
    EXPECT_GE(r.begins[i].index, 1);
    EXPECT_LE(r.begins[i].index, r.begins[i].count);
    if (i) {
      EXPECT_GT(r.begins[i].index, r.begins[i - 1].index);
      EXPECT_EQ(r.begins[i].count, r.begins[0].count);
    }
  }
  ASSERT_FALSE(r.overall.empty());
  for (std::size_t i = 0; i < r.overall.size(); ++i) {
    EXPECT_GE(r.overall[i], 0.0);
    EXPECT_LE(r.overall[i], 1.0);
    EXPECT_GE(r.stage[i], 0.0);
    EXPECT_LE(r.stage[i], 1.0);
    if (i) {
      EXPECT_GE(r.overall[i], r.overall[i - 1]) << "overall went back at report " << i;
    }
  }
  EXPECT_EQ(r.overall.back(), 1.0);
}

}  // namespace

TEST(Progress, EveryStageIsAnnouncedAndOverallNeverGoesBack) {
  // Closed: auto classifies once, and the planned clean and second pass are skipped.
  Recorder closed;
  FillOptions o = small_job();
  o.progress = &closed;
  const FillResult a = fill(test::make_box({0, 0, 0}, {12, 12, 12}), o);
  expect_well_formed(closed, a.report);
  EXPECT_EQ(closed.begins.front().name, "review");
  EXPECT_EQ(closed.begins[1].name, "spatial");
  EXPECT_LT(closed.begins.size(), static_cast<std::size_t>(closed.begins[0].count));
  // With a hole: auto classifies, cleans and classifies again; one plan, no restart at 0 %.
  Recorder open;
  o.progress = &open;
  const FillResult b = fill(test::make_box_with_hole({0, 0, 0}, {12, 12, 12}), o);
  expect_well_formed(open, b.report);
  int classifies = 0;
  for (const auto& s : open.begins) classifies += s.name == "classify";
  EXPECT_EQ(classifies, 2);
  // Depth grading and measuring add their stages to the plan.
  Recorder more;
  o.progress = &more;
  o.measure = true;
  o.design.grading.push_back(
      {Graded::Porosity, {.shape = RampShape::Depth, .start = 0.5, .end = 0.7}});
  const FillResult c = fill(test::make_box({0, 0, 0}, {12, 12, 12}), o);
  expect_well_formed(more, c.report);
}

TEST(Progress, CancellingFromReportThrowsAndReturnsNothing) {
  Recorder r;
  r.cancel_after = 3;
  FillOptions o = small_job();
  o.progress = &r;
  EXPECT_THROW(fill(test::make_box({0, 0, 0}, {12, 12, 12}), o), Cancelled);
}

TEST(Progress, AnnouncementsDoNotDependOnTheThreadCount) {
  auto run = [](std::size_t threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Recorder r;
    FillOptions o = small_job();
    o.progress = &r;
    fill(test::make_box_with_hole({0, 0, 0}, {12, 12, 12}), o);
    std::vector<std::string> names;
    for (const auto& b : r.begins) names.push_back(b.name + "#" + std::to_string(b.index));
    return names;
  };
  EXPECT_EQ(run(1), run(8));
}
