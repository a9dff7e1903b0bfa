#pragma once
// Temporal consistency per cell (seed 4.2.4): counters O (obstacle votes) and S (free votes);
// no decision before O+S >= min_observations; obstacle if O/(O+S) > obstacle_ratio; label flips
// counted in I; at I >= permanent_flips the cell is an obstacle for good.
// Storage: a flat ring buffer of n x n slots addressed by global cell modulo n, each slot tagged
// with its global cell, so the window scrolls with the wearer without moving memory; a slot
// re-used for a new global cell starts unknown.
#include <cstdint>
#include <unordered_set>
#include <vector>

#include <assistive_obstacles/cell_values.h>
#include <assistive_obstacles/params.h>

namespace assistive_obstacles
{
struct CellCounters
{
  int32_t gx = 0, gy = 0;   ///< global cell this slot holds
  uint16_t o = 0, s = 0;    ///< obstacle / free votes (weighted)
  uint16_t step = 0;        ///< free votes that were steps (weighted)
  uint16_t votes = 0;       ///< number of votes (unweighted, saturating): decide after min_observations
  uint16_t flips = 0;       ///< I
  int8_t state = CELL_UNKNOWN;   ///< CELL_UNKNOWN (undecided), CELL_FREE or CELL_OBSTACLE
  uint8_t clear = 0;        ///< height bands seen clear since the last obstacle evidence (column_bands)
  bool used = false;
  bool permanent = false;
};

class TemporalFilter
{
public:
  explicit TemporalFilter(const ObstaclesParams& p = ObstaclesParams()) { setParams(p); }
  void setParams(const ObstaclesParams& p);
  /// Ring size (cells per side); clears everything when it changes.
  void resize(int n);
  int size() const { return n_; }

  /// Adds one frame's vote for global cell (gx, gy). `weight` (1..MAX_VOTE_WEIGHT) lets near,
  /// precise observations count more than far, noisy ones; the seed's rule is weight 1.
  /// `observed` = false: an inferred label (the closing filled the cell); it adds to the counters
  /// but not to the number of votes, so a cell never observed itself is never decided.
  void vote(int gx, int gy, FrameLabel label, int weight = 1, bool observed = true);
  static constexpr int MAX_VOTE_WEIGHT = 4;
  /// Column clearance (column_bands > 0; ObstacleMap applies the rule): the bands of (gx, gy)
  /// seen clear this frame are set in the cell's bits, those seen occupied (obstacle evidence this
  /// frame, at any range) cleared; occupied wins. A new cell starts with the bands below
  /// column_strict_from set (presumed clear until an obstacle is seen in them).
  void observeColumn(int gx, int gy, uint8_t seen_clear, uint8_t seen_occupied);
  /// Ghost-free hook (issue 22): global cells covered by a mover (a person walking) this frame.
  /// vote() and observeColumn() skip them: a passer-by neither votes obstacle (no ghost) nor
  /// flips the cell (no permanent lock), and withdraws no column clearance. Holds until replaced;
  /// an empty list (the default) changes nothing.
  void setMoverCells(const std::vector<std::pair<int, int>>& cells);
  void clearMoverCells() { movers_.clear(); }
  bool moverCell(int gx, int gy) const { return !movers_.empty() && movers_.count(key(gx, gy)) > 0; }
  /// Whether every band of the cell's column was seen clear since its last obstacle evidence
  /// (always true when column_bands is 0).
  bool columnClear(int gx, int gy) const;
  /// Output code of global cell (gx, gy): CELL_UNKNOWN, CELL_FREE, CELL_STEP or CELL_OBSTACLE.
  int8_t code(int gx, int gy) const;
  /// Counters of a cell (nullptr when the slot holds another cell or was never used).
  const CellCounters* find(int gx, int gy) const;
  void clear();
  /// Forgets every cell outside [ox, ox+n) x [oy, oy+n) (the window scrolled away from it).
  void retain(int ox, int oy, int n);

private:
  static int64_t key(int gx, int gy) { return (static_cast<int64_t>(gx) << 32) ^ static_cast<uint32_t>(gy); }
  int slot(int gx, int gy) const;
  CellCounters& claim(int gx, int gy);
  ObstaclesParams params_;
  uint8_t presumed_clear_ = 0;  ///< bands a new cell starts with (below column_strict_from)
  int n_ = 0;
  std::vector<CellCounters> cells_;
  std::unordered_set<int64_t> movers_;  ///< key(gx, gy) of the mover cells
};

}  // namespace assistive_obstacles
