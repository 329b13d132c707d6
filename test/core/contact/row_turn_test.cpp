// contact.row_turn: an activation loop keeps a contact's normal row of H,
// and the row's entries of W, from the loop before while its points and
// normal stay and its element's node tangents turned by at most row_turn.
// The reference is the loop that forms every row again at its iterate
// (row_turn 0): each step from one state both ways, the answers must obey
// Signorini's law alike and lie within the penetration tolerance of each
// other, in as many loops.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "endovascular_sim/sim/simulation.h"
#include "signorini_check.h"

namespace evsim {
namespace {

// The coil of `aneurysm_packed` filling its dome (t = 4.5-4.8 s, 60-100
// rows, W from the band of A^-1): each loop's correction turns its
// elements by up to 1e-2 rad, and most rows' points and normals stay from
// loop to loop.
TEST(RowTurn, KeptRowsGiveTheAnswerOfRowsFormedEveryLoop) {
  SceneModel kept = loadScene("aneurysm_packed");
  ASSERT_GT(kept.contact.row_turn, 0.0);  // the default keeps rows
  SceneModel formed = kept;
  formed.contact.row_turn = 0.0;
  const double tol = std::max(kept.contact.penetration_tolerance, kept.contact.pair_tolerance);
  long rows_kept = 0, rows_formed = 0, later_rows = 0;
  test::BothWays t;  // a: rows kept, b: formed every loop
  ASSERT_NO_FATAL_FAILURE(test::stepBothWays(
      kept, formed, 4500, 300, [&](int k, const SimData& d, const SimData& other) {
        test::expectWithinTolerance(d, tol, k);
        t.add(d, other);
        rows_kept += d.stats.contact.kept_rows;
        rows_formed += other.stats.contact.kept_rows;
        if (d.stats.contact.activation_loops > 1)
          later_rows += (d.stats.contact.activation_loops - 1) * d.stats.contact.contacts;
      }));
  std::printf(
      "[ metric   ] aneurysm_packed t = 4.5-4.8 s: loops %ld kept, %ld formed every loop; rows of "
      "the later loops (about %ld) whose W was kept: %ld, %ld formed every loop (unmoved); "
      "largest |gap| of an active contact %.3g m kept, %.3g m formed; answers %.3g m apart at "
      "most\n",
      t.loops_a, t.loops_b, later_rows, rows_kept, rows_formed, t.gap_a, t.gap_b, t.apart);
  // Formed every loop, a row is the same only where its element did not
  // move; kept, most of the later loops' rows are.
  EXPECT_GT(rows_kept, later_rows / 2);
  EXPECT_GT(rows_kept, 2 * rows_formed);
  EXPECT_LE(t.gap_a, tol);
  EXPECT_LE(t.gap_b, tol);
  EXPECT_LE(t.apart, tol);
  EXPECT_LE(t.loops_a, t.loops_b + t.loops_b / 20);
}

// A scene's row_turn out of its range is refused by the options' check.
TEST(RowTurn, OutOfRangeIsRefused) {
  ContactOptions o;
  o.row_turn = -1e-3;
  EXPECT_NE(validateContactOptions(o).find("row_turn"), std::string::npos);
  o.row_turn = 0.2;
  EXPECT_NE(validateContactOptions(o).find("row_turn"), std::string::npos);
  o.row_turn = 0.0;
  EXPECT_EQ(validateContactOptions(o), "");
}

}  // namespace
}  // namespace evsim
