// The viewer's pure parts that need no display: the window layout from the window's size and
// the splitters' positions (layout.h), the cost chart's value axis and hit testing
// (cost_chart.h), the states table's sorting (states_table.h) and the script steps that move
// a splitter, press the help key or choose a tab (script.h).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/view/cost_chart.h"
#include "app/view/layout.h"
#include "app/view/script.h"
#include "app/view/states_table.h"
#include "core/base/error.h"

namespace {

using gs::app::lay_out_window;
using gs::app::Rect;
using gs::app::SplitterPositions;
using gs::app::WindowLayout;

float overlap(const Rect& a, const Rect& b) {
  const float w = std::min(a.right(), b.right()) - std::max(a.x, b.x);
  const float h = std::min(a.bottom(), b.bottom()) - std::max(a.y, b.y);
  return w > 0 && h > 0 ? w * h : 0.0f;
}

// The five parts lie inside the window, none overlaps another and together they cover it.
void expect_tiles(const WindowLayout& layout, float width, float height) {
  const std::vector<Rect> parts = {layout.viewport, layout.right_splitter, layout.controls,
                                   layout.bottom_splitter, layout.bottom};
  float area = 0;
  for (size_t i = 0; i < parts.size(); ++i) {
    const Rect& r = parts[i];
    EXPECT_GE(r.w, 0.0f) << i;
    EXPECT_GE(r.h, 0.0f) << i;
    EXPECT_GE(r.x, 0.0f) << i;
    EXPECT_GE(r.y, 0.0f) << i;
    EXPECT_LE(r.right(), width + 1e-3f) << i;
    EXPECT_LE(r.bottom(), height + 1e-3f) << i;
    area += r.w * r.h;
    for (size_t j = i + 1; j < parts.size(); ++j) EXPECT_EQ(overlap(r, parts[j]), 0.0f) << i << j;
  }
  EXPECT_NEAR(area, width * height, 1e-3f * width * height);
}

TEST(ViewLayout, UndraggedPanelsTakeAShareOfTheWindowWithinBounds) {
  // 1024x640: 30% of each side (307.2, rounded to 307, and 192), both within their bounds.
  WindowLayout small = lay_out_window(1024, 640, {});
  EXPECT_FLOAT_EQ(small.controls.w, 307.0f);
  EXPECT_FLOAT_EQ(small.viewport.w, 1024 - 307 - gs::app::kSplitterThickness);
  EXPECT_FLOAT_EQ(small.bottom.h, 192.0f);
  EXPECT_FLOAT_EQ(small.viewport.h, 640 - 192 - gs::app::kSplitterThickness);
  expect_tiles(small, 1024, 640);
  // 1920x1080: the shares (576, 324) are capped at 420 and 300.
  WindowLayout large = lay_out_window(1920, 1080, {});
  EXPECT_FLOAT_EQ(large.controls.w, 420.0f);
  EXPECT_FLOAT_EQ(large.bottom.h, 300.0f);
  EXPECT_FLOAT_EQ(large.viewport.w, 1494.0f);
  EXPECT_FLOAT_EQ(large.viewport.h, 774.0f);
  expect_tiles(large, 1920, 1080);
  // The bottom panel sits under the viewport, the controls beside both.
  EXPECT_FLOAT_EQ(large.bottom.w, large.viewport.w);
  EXPECT_FLOAT_EQ(large.controls.h, 1080.0f);
  EXPECT_FLOAT_EQ(large.controls.x, large.viewport.w + gs::app::kSplitterThickness);
}

TEST(ViewLayout, DraggedPanelsKeepTheirSizeWithinTheMinimums) {
  const WindowLayout wide = lay_out_window(1280, 800, SplitterPositions{500, 350});
  EXPECT_FLOAT_EQ(wide.controls.w, 500.0f);
  EXPECT_FLOAT_EQ(wide.viewport.w, 774.0f);
  EXPECT_FLOAT_EQ(wide.bottom.h, 350.0f);
  EXPECT_FLOAT_EQ(wide.viewport.h, 444.0f);
  expect_tiles(wide, 1280, 800);
  // Too narrow: the panels' minimums.
  const WindowLayout narrow = lay_out_window(1280, 800, SplitterPositions{50, 20});
  EXPECT_FLOAT_EQ(narrow.controls.w, gs::app::kControlsMinWidth);
  EXPECT_FLOAT_EQ(narrow.bottom.h, gs::app::kBottomMinHeight);
  expect_tiles(narrow, 1280, 800);
  // Too wide: the viewport keeps a usable size.
  const WindowLayout greedy = lay_out_window(1280, 800, SplitterPositions{5000, 5000});
  EXPECT_FLOAT_EQ(greedy.viewport.w, gs::app::kMinViewportDrag);
  EXPECT_FLOAT_EQ(greedy.viewport.h, gs::app::kMinViewportDrag);
  expect_tiles(greedy, 1280, 800);
}

TEST(ViewLayout, AWindowSmallerThanThePanelsMinimumsStillTiles) {
  // The viewport keeps its 16 units, the panels get what is left.
  for (const float side : {100.0f, 300.0f}) {
    const WindowLayout tiny = lay_out_window(side, side, SplitterPositions{});
    EXPECT_FLOAT_EQ(tiny.viewport.w, gs::app::kMinViewport) << side;
    EXPECT_FLOAT_EQ(tiny.controls.w, side - gs::app::kMinViewport - gs::app::kSplitterThickness);
    expect_tiles(tiny, side, side);
  }
  // Narrower than the viewport's 16 units and a bar: nothing of negative size.
  const WindowLayout sliver = lay_out_window(4, 4, SplitterPositions{});
  EXPECT_EQ(sliver.controls.w, 0.0f);
  EXPECT_EQ(sliver.bottom.h, 0.0f);
}

TEST(ViewLayout, ChartScaleStepsAreOneTwoOrFiveTimesAPowerOfTen) {
  struct Case {
    double largest, top, step;
  };
  for (const Case& c : std::vector<Case>{{425.2, 500, 100},
                                         {8217, 10000, 2000},
                                         {1.0, 1.0, 0.2},
                                         {7, 8, 2},
                                         {88.95, 100, 20},
                                         {0.034, 0.04, 0.01},
                                         {500, 500, 100}}) {
    const gs::app::ChartScale scale = gs::app::nice_scale(c.largest);
    EXPECT_NEAR(scale.top, c.top, 1e-9 * c.top) << c.largest;
    EXPECT_NEAR(scale.step, c.step, 1e-9 * c.step) << c.largest;
    EXPECT_GE(scale.top, c.largest);
  }
  for (const double nothing : {0.0, -3.0}) {
    EXPECT_EQ(gs::app::nice_scale(nothing).top, 1.0);
    EXPECT_EQ(gs::app::nice_scale(nothing).step, 0.2);
  }
}

TEST(ViewLayout, ChartSlotUnderThePointer) {
  // Four slots of 25 units from x = 10.
  EXPECT_EQ(gs::app::slot_at(10.0f, 10, 100, 4), 0);
  EXPECT_EQ(gs::app::slot_at(34.9f, 10, 100, 4), 0);
  EXPECT_EQ(gs::app::slot_at(35.0f, 10, 100, 4), 1);
  EXPECT_EQ(gs::app::slot_at(109.9f, 10, 100, 4), 3);
  EXPECT_EQ(gs::app::slot_at(110.0f, 10, 100, 4), -1);
  EXPECT_EQ(gs::app::slot_at(9.9f, 10, 100, 4), -1);
  EXPECT_EQ(gs::app::slot_at(50.0f, 10, 100, 0), -1);
}

TEST(ViewLayout, StatesSortByAnyColumnTiesByState) {
  using gs::app::StateColumn;
  const std::vector<gs::StateRow> rows = {
      {3, 0, 20, 5, 100}, {1, 2, 400, 5, 7}, {2, 1, 20, 9, 100}, {0, 0, 8, 1, 0}};
  const auto order = [&](StateColumn column, bool descending) {
    std::vector<gs::StateRow> sorted = rows;
    gs::app::sort_state_rows(sorted, column, descending);
    std::vector<uint32_t> states;
    for (const gs::StateRow& row : sorted) states.push_back(row.state);
    return states;
  };
  EXPECT_EQ(order(StateColumn::state, false), (std::vector<uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(order(StateColumn::axis, false), (std::vector<uint32_t>{0, 3, 2, 1}));
  EXPECT_EQ(order(StateColumn::granularity, true), (std::vector<uint32_t>{1, 2, 3, 0}));
  EXPECT_EQ(order(StateColumn::voxels, false), (std::vector<uint32_t>{0, 1, 3, 2}));
  EXPECT_EQ(order(StateColumn::rays, true), (std::vector<uint32_t>{2, 3, 1, 0}));
}

TEST(ViewLayout, ScriptStepsMoveSplittersPressTheHelpKeyAndChooseTabs) {
  const std::vector<gs::app::ScriptStep> steps = gs::app::parse_script(
      "frame 3: drag-splitter right -120\nframe 4: drag-splitter bottom 40\nframe 5: key F1\n"
      "frame 6: key ?\nframe 7: tab states\n",
      "s.txt");
  ASSERT_EQ(steps.size(), 5u);
  using Action = gs::app::ScriptStep::Action;
  EXPECT_EQ(steps[0].action, Action::drag_splitter);
  EXPECT_EQ(steps[0].splitter, gs::app::Splitter::right);
  EXPECT_EQ(steps[0].pixels, -120);
  EXPECT_EQ(steps[1].splitter, gs::app::Splitter::bottom);
  EXPECT_EQ(steps[1].pixels, 40);
  EXPECT_EQ(steps[2].action, Action::help_key);
  EXPECT_EQ(steps[3].action, Action::help_key);
  EXPECT_EQ(steps[4].action, Action::tab);
  EXPECT_EQ(steps[4].name, "states");
  for (const std::string bad :
       {"drag-splitter left 5", "drag-splitter right", "drag-splitter right 5px",
        "drag-splitter bottom 99999", "key F2", "key", "key F1 F1", "tab cost", "tab"}) {
    try {
      gs::app::parse_script("# fine\n\nframe 2: " + bad + "\n", "s.txt");
      ADD_FAILURE() << bad << " was accepted";
    } catch (const gs::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("s.txt:3: "), std::string::npos) << e.what();
    }
  }
}

}  // namespace
