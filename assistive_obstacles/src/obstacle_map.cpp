#include <assistive_obstacles/obstacle_map.h>

#include <optional>

#include <assistive_obstacles/column_clearance.h>

#include <algorithm>
#include <cmath>

namespace assistive_obstacles
{
namespace
{
enum class DepthCheck
{
  OUTSIDE,     ///< not in the image or out of range
  CONSISTENT,  ///< depth there matches the cell
  OCCLUDED,    ///< something nearer hides the cell
  VANISHED,    ///< no depth at that pixel
  THROUGH,     ///< depth passes through the cell (glass?)
};

DepthCheck checkDepth(const Eigen::Vector3f& p_world, const Eigen::Isometry3f& T_cam_world,
                      const StereoModel& m, const cv::Mat& disp, double min_z, double max_z, float tol)
{
  const Eigen::Vector3f pc = T_cam_world * p_world;
  if (!(pc.z() >= min_z && pc.z() <= max_z)) return DepthCheck::OUTSIDE;
  const double sx = static_cast<double>(disp.cols) / m.width, sy = static_cast<double>(disp.rows) / m.height;
  const double u = (m.fx * pc.x() / pc.z() + m.cx + 0.5) * sx - 0.5;
  const double v = (m.fy * pc.y() / pc.z() + m.cy + 0.5) * sy - 0.5;
  const int iu = static_cast<int>(std::lround(u)), iv = static_cast<int>(std::lround(v));
  if (iu < 2 || iv < 2 || iu >= disp.cols - 2 || iv >= disp.rows - 2) return DepthCheck::OUTSIDE;
  const float d = disp.at<float>(iv, iu);
  if (!(d > 0.f)) return DepthCheck::VANISHED;
  const float z = static_cast<float>(m.fx * sx * m.baseline) / d;
  // Compare along the ray: the measured point's distance vs the cell's.
  if (z < pc.z() - tol) return DepthCheck::OCCLUDED;
  if (z > pc.z() + tol) return DepthCheck::THROUGH;
  return DepthCheck::CONSISTENT;
}

/// Dropout / glass: the depth image shows nothing at a mapped obstacle's column (0.5 m and 1.2 m
/// above the feet): no depth or depth passing through it, and nothing consistent or in front.
bool depthMissesColumn(float x, float y, float feet, const Eigen::Isometry3f& T_cam_world, const StereoModel& m,
                       const cv::Mat& disp, const ObstaclesParams& params, float tol)
{
  int bad = 0, good = 0;
  for (const float hz : {0.5f, 1.2f})
  {
    const Eigen::Vector3f p(x, y, feet + hz);
    const DepthCheck dc = checkDepth(p, T_cam_world, m, disp, params.min_depth, params.dropout_max_range, tol);
    if (dc == DepthCheck::VANISHED || dc == DepthCheck::THROUGH) ++bad;
    if (dc == DepthCheck::CONSISTENT || dc == DepthCheck::OCCLUDED) ++good;
  }
  return bad > 0 && good == 0;
}

/// The cells (global indices) the movers' discs overlap (disc vs cell square).
std::vector<std::pair<int, int>> moverCells(const std::vector<MoverFootprint>& movers, double res, double window_radius)
{
  std::vector<std::pair<int, int>> cells;
  for (const MoverFootprint& m : movers)
  {
    // A footprint wider than the window is no person (and would loop over huge ranges).
    if (!std::isfinite(m.x) || !std::isfinite(m.y) || !(m.radius > 0.0) || m.radius > window_radius) continue;
    const int x0 = static_cast<int>(std::floor((m.x - m.radius) / res)), x1 = static_cast<int>(std::floor((m.x + m.radius) / res));
    const int y0 = static_cast<int>(std::floor((m.y - m.radius) / res)), y1 = static_cast<int>(std::floor((m.y + m.radius) / res));
    for (int gy = y0; gy <= y1; ++gy)
      for (int gx = x0; gx <= x1; ++gx)
      {
        const double dx = std::max({gx * res - m.x, 0.0, m.x - (gx + 1) * res});
        const double dy = std::max({gy * res - m.y, 0.0, m.y - (gy + 1) * res});
        if (dx * dx + dy * dy < m.radius * m.radius) cells.emplace_back(gx, gy);
      }
  }
  return cells;
}

/// Squared horizontal distance (m^2) from `t` to the centre of local cell (lx, ly).
double range2(const Window& w, int lx, int ly, const Eigen::Vector3f& t)
{
  const double dx = w.centerX(lx) - t.x(), dy = w.centerY(ly) - t.y();
  return dx * dx + dy * dy;
}
}  // namespace

double obstacleEvidenceRange(const ObstaclesParams& p, const StereoModel& m)
{
  const double fb = m.fx * m.baseline;  // full-resolution px * m
  if (!(p.obstacle_max_sigma > 0.0) || !(p.disparity_sigma > 0.0) || !(fb > 0.0)) return 0.0;
  return std::sqrt(p.obstacle_max_sigma * fb / p.disparity_sigma);
}

ObstacleMap::ObstacleMap(const ObstaclesParams& p) { setParams(p); }

void ObstacleMap::setParams(const ObstaclesParams& p)
{
  params_ = p;
  elevation_.setParams(p);
  mls_.setParams(p);
  temporal_.setParams(p);
  sonar_.setParams(p);
  const Window w = Window::around(0.0, 0.0, p.window_radius, p.cell_size);
  temporal_.resize(w.n);
  if (!octree_) octree_.reset(new SeenOctree(p));
}

void ObstacleMap::reset()
{
  temporal_.clear();
  sonar_.clear();
  octree_.reset(new SeenOctree(params_));
  world_.clear();
}

void ObstacleMap::update(const std::vector<Eigen::Vector3f>& points_cam, const Eigen::Isometry3f& T_world_cam,
                         const StereoModel* camera, const cv::Mat* disparity,
                         const std::vector<Eigen::Vector3f>* normals_cam)
{
  stats_ = FrameStats();
  stats_.points_in = points_cam.size();
  world_.resize(points_cam.size());
  const Eigen::Matrix3f R = T_world_cam.linear();
  const Eigen::Vector3f t = T_world_cam.translation();
  for (size_t i = 0; i < points_cam.size(); ++i) world_[i] = R * points_cam[i] + t;
  last_origin_ = t;
  const float feet = t.z() - static_cast<float>(params_.camera_height);
  const float elevated = feet + static_cast<float>(params_.step_height);  // above this: not walkable
  if (params_.surface_push > 0.0) pushIntoSurfaces(R, t, normals_cam, elevated);

  window_ = Window::around(t.x(), t.y(), params_.window_radius, params_.cell_size);
  temporal_.resize(window_.n);
  temporal_.retain(window_.ox, window_.oy, window_.n);
  // Ghost-free hook: the cells this frame's movers overlap.
  if (!movers_.empty()) temporal_.setMoverCells(moverCells(movers_, window_.res, params_.window_radius));
  sonar_.retain(window_);
  last_feet_ = feet;
  const float z_max = t.z() + static_cast<float>(params_.head_clearance);
  elevation_.build(world_, window_, z_max, elevated);
  stats_.points_binned = elevation_.binnedPoints();
  mls_.classify(elevation_, feet, labels_);
  voteCells(T_world_cam, camera, disparity, feet);
  // The movers were this frame's.
  if (!movers_.empty()) temporal_.clearMoverCells();
  movers_.clear();
}

void ObstacleMap::pushIntoSurfaces(const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                                   const std::vector<Eigen::Vector3f>* normals_cam, float elevated)
{
  // A camera sees the front face of a solid; the solid lies behind it. Points are moved that far
  // into it, so a face on a cell border lands in the solid's cell: points of steep surfaces along
  // the surface's horizontal normal when known (a wall seen at a grazing angle: the ray runs along
  // the wall and would not move the point off the border), else elevated points along the
  // horizontal viewing ray.
  const float push = static_cast<float>(params_.surface_push);
  const bool use_normals = usesNormals() && normals_cam && normals_cam->size() == world_.size();
  for (size_t i = 0; i < world_.size(); ++i)
  {
    Eigen::Vector3f& p = world_[i];
    float dx = 0.f, dy = 0.f;
    const Eigen::Vector3f into = use_normals ? Eigen::Vector3f(-(R * (*normals_cam)[i])) : Eigen::Vector3f::Zero();
    // A steep surface (horizontal normal part >= 0.5) at any height, a wall's foot included; a
    // table top or the floor is not pushed along its normal.
    if (use_normals && into.head<2>().squaredNorm() >= 0.25f * into.squaredNorm())
    {
      dx = into.x();
      dy = into.y();
    }
    else if (p.z() > elevated)
    {
      dx = p.x() - t.x();
      dy = p.y() - t.y();
    }
    else
      continue;
    const float d = std::sqrt(dx * dx + dy * dy);
    if (d > 1e-3f)
    {
      p.x() += push * dx / d;
      p.y() += push * dy / d;
    }
  }
}

void ObstacleMap::voteCells(const Eigen::Isometry3f& T_world_cam, const StereoModel* camera,
                            const cv::Mat* disparity, float feet)
{
  const Eigen::Vector3f t = T_world_cam.translation();
  const int n = window_.n;
  dropout_.origin_x = window_.ox * window_.res;
  dropout_.origin_y = window_.oy * window_.res;
  dropout_.resolution = window_.res;
  dropout_.width = dropout_.height = n;
  dropout_.data.assign(static_cast<size_t>(n) * n, CELL_UNKNOWN);
  const bool check_depth = camera && disparity && !disparity->empty() && disparity->type() == CV_32F;
  const Eigen::Isometry3f T_cam_world = T_world_cam.inverse();
  const float tol = static_cast<float>(std::max(0.3, 1.5 * params_.cell_size));

  const double vote_r2 = params_.vote_max_range * params_.vote_max_range;
  const double obstacle_r = camera ? obstacleEvidenceRange(params_, *camera) : 0.0;
  const double obstacle_r2 = obstacle_r * obstacle_r;
  const double full_r2 = params_.full_weight_range * params_.full_weight_range;
  // Column clearance: which height bands of each column this frame saw clear. Without a depth
  // image the rule cannot judge and is off (every band counts as seen).
  std::optional<ColumnClearance> columns;
  if (check_depth && params_.column_bands > 0) columns.emplace(params_, *camera, *disparity, T_world_cam, feet);
  const uint8_t all_bands = allBands(params_.column_bands);
  for (int ly = 0; ly < n; ++ly)
    for (int lx = 0; lx < n; ++lx)
    {
      if (!window_.inCircle(lx, ly)) continue;
      if (vote_r2 > 0.0 && range2(window_, lx, ly, t) > vote_r2) continue;
      const int c = window_.index(lx, ly);
      const int gx = window_.ox + lx, gy = window_.oy + ly;
      const float x = static_cast<float>(window_.centerX(lx)), y = static_cast<float>(window_.centerY(ly));
      if (elevation_.count(c) > 0) ++stats_.cells_observed;
      if (temporal_.moverCell(gx, gy))
      {
        ++stats_.mover_cells;
        continue;
      }
      FrameLabel lab = labels_[c];
      // An obstacle label at any range (even one too far to vote) withdraws the clearance of the
      // bands its points are in.
      // A band hidden just in front while this frame labels the cell's floor is withdrawn too:
      // something overhangs the seen floor (a shelf's front face hides the space above the floor
      // behind it, and no point of the shelf falls in the cells under it).
      if (params_.column_bands > 0)
      {
        const ColumnClearance::Bits seen = columns ? columns->bits(x, y) : ColumnClearance::Bits{all_bands, 0};
        const bool floor_seen = lab == FrameLabel::FREE || lab == FrameLabel::STEP;
        temporal_.observeColumn(gx, gy, seen.clear,
                                (lab == FrameLabel::OBSTACLE && !mls_.filled()[c]
                                     ? columnOccupiedBits(params_, feet, elevation_.heights(c), elevation_.count(c))
                                     : 0) |
                                    (floor_seen ? seen.blocked : 0));
      }
      // Dropout / glass: a mapped obstacle seen "through" or without depth keeps its label.
      const bool dropout = check_depth && temporal_.code(gx, gy) == CELL_OBSTACLE && lab != FrameLabel::OBSTACLE &&
                           depthMissesColumn(x, y, feet, T_cam_world, *camera, *disparity, params_, tol);
      if (dropout)
      {
        dropout_.data[c] = CELL_OBSTACLE;
        ++stats_.dropout_cells;
        if (params_.dropout_free_weight <= 0)
        {
          lab = FrameLabel::NONE;
          labels_[c] = FrameLabel::NONE;
        }
      }
      if (lab == FrameLabel::OBSTACLE) ++stats_.obstacle_votes;
      if (lab == FrameLabel::FREE || lab == FrameLabel::STEP) ++stats_.free_votes;
      int weight = 1;
      if (params_.full_weight_range > 0.0)
        weight = static_cast<int>(std::lround(TemporalFilter::MAX_VOTE_WEIGHT *
                                              std::min(1.0, full_r2 / std::max(1e-6, range2(window_, lx, ly, t)))));
      // A mapped obstacle seen through / without depth takes only a weak free vote: glass stays an
      // obstacle for a while, but a false obstacle on the floor is not locked for good.
      if (dropout) weight = std::min(weight, params_.dropout_free_weight);
      // The closing's label is inferred, not seen: a weak vote that never decides a cell on its own.
      const bool filled = mls_.filled()[c] != 0;
      if (filled) weight = std::min(weight, params_.closing_weight);
      // Obstacle evidence only where stereo depth is precise enough to put a surface in the right
      // cell (sigma_Z = Z^2 sigma_d / (f B) grows with range^2: a wall seen from afar spills its
      // points into the cells in front of and behind it). For the same reason a cell judged to
      // hold only a neighbour's spill takes no free vote from there either (it may be the edge
      // of the obstacle itself: parking's columns and cars).
      if (obstacle_r2 > 0.0 && (lab == FrameLabel::OBSTACLE || mls_.spill()[c] || (lab == FrameLabel::STEP && !params_.far_step_votes)) &&
          range2(window_, lx, ly, t) > obstacle_r2)
        continue;
      // A cell the ranger hit is never freed by camera rays (they may have passed through glass).
      if (lab != FrameLabel::OBSTACLE && sonar_.held(gx, gy)) continue;
      // Floor seen is not the column seen: a free vote counts only once every band of the column
      // was seen clear since its last obstacle evidence.
      if ((lab == FrameLabel::FREE || lab == FrameLabel::STEP) && !temporal_.columnClear(gx, gy)) continue;
      temporal_.vote(gx, gy, lab, weight, !filled);
    }
}

RangeCheck ObstacleMap::addRange(const RangeReading& r)
{
  if (!params_.sonar_enabled) return SonarFusion::check(r);
  const float z_top = last_origin_.z() + static_cast<float>(params_.head_clearance);
  // Does the camera's last frame hold a surface inside the cone at the echo's range? Then the echo
  // is that (opaque) surface, mapped or not yet (beyond the camera's obstacle evidence range):
  // the ranger adds nothing. Glass leaves no point there (the camera's depth passes through it).
  bool camera_surface = false;
  if (SonarFusion::check(r) == RangeCheck::ECHO && !world_.empty())
  {
    const Eigen::Vector3f o = r.T_world_sensor.translation();
    const Eigen::Vector3f axis = r.T_world_sensor.linear().col(0).normalized();
    const float cos_half = static_cast<float>(std::cos(0.5 * r.field_of_view));
    const float tol = static_cast<float>(2.0 * params_.cell_size);  // stereo depth noise at 2-4 m
    const float lo = static_cast<float>(r.range) - tol, hi = static_cast<float>(r.range) + tol;
    const float z_low = last_feet_ + static_cast<float>(params_.step_height);
    int hits = 0;
    for (const Eigen::Vector3f& p : world_)
    {
      if (p.z() < z_low || p.z() > z_top) continue;
      const Eigen::Vector3f d = p - o;
      const float n = d.norm();
      if (n < lo || n > hi || d.dot(axis) < cos_half * n) continue;
      if (++hits >= 3)  // a few points: a textureless wall gives few
      {
        camera_surface = true;
        break;
      }
    }
  }
  return sonar_.apply(r, window_, last_feet_, z_top, temporal_, camera_surface);
}

void ObstacleMap::insertOctomap()
{
  if (params_.octomap_enabled && !world_.empty()) octree_->insert(world_, last_origin_);
}

void ObstacleMap::grid(GridData& out) const
{
  const int n = window_.n;
  out.origin_x = window_.ox * window_.res;
  out.origin_y = window_.oy * window_.res;
  out.resolution = window_.res;
  out.width = out.height = n;
  out.data.assign(static_cast<size_t>(n) * n, CELL_UNKNOWN);
  for (int ly = 0; ly < n; ++ly)
    for (int lx = 0; lx < n; ++lx)
    {
      const int gx = window_.ox + lx, gy = window_.oy + ly;
      // A cell the ranger hit is an obstacle from that echo on, whatever the filter's counters
      // still say from camera rays that passed through it before (a panel seen through).
      const int8_t code = sonar_.held(gx, gy) ? CELL_OBSTACLE : temporal_.code(gx, gy);
      // A free cell whose column took obstacle evidence since is no longer known free.
      out.data[window_.index(lx, ly)] =
          (code == CELL_FREE || code == CELL_STEP) && !temporal_.columnClear(gx, gy) ? CELL_UNKNOWN : code;
    }
}

}  // namespace assistive_obstacles
