#include <assistive_eval/plots.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace assistive_eval
{
namespace
{
const cv::Scalar BLACK(0, 0, 0), WHITE(255, 255, 255), GREY(150, 150, 150);

std::string fmt(double v, int prec = 1)
{
  std::ostringstream os;
  os << std::fixed << std::setprecision(prec) << v;
  return os.str();
}

double niceStep(double range, int target_ticks)
{
  const double raw = range / std::max(1, target_ticks);
  const double p = std::pow(10.0, std::floor(std::log10(std::max(raw, 1e-9))));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw)
      return m * p;
  return 10.0 * p;
}

/// World rectangle -> image pixels, equal scale on both axes (or not), y up.
struct Axes
{
  double x0, x1, y0, y1;  // world bounds
  int left = 70, right = 20, top = 40, bottom = 60;
  int W, H;
  double sx, sy;
  Axes(double ax0, double ax1, double ay0, double ay1, int w, int h, bool equal) : W(w), H(h)
  {
    if (!(ax1 > ax0))
    {
      ax0 -= 0.5;
      ax1 += 0.5;
    }
    if (!(ay1 > ay0))
    {
      ay0 -= 0.5;
      ay1 += 0.5;
    }
    const double mx = 0.05 * (ax1 - ax0), my = 0.05 * (ay1 - ay0);
    x0 = ax0 - mx;
    x1 = ax1 + mx;
    y0 = ay0 - my;
    y1 = ay1 + my;
    sx = (W - left - right) / (x1 - x0);
    sy = (H - top - bottom) / (y1 - y0);
    if (equal)
    {
      const double s = std::min(sx, sy);
      // grow the world range of the axis with spare pixels so the data stays centred
      const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
      x0 = cx - 0.5 * (W - left - right) / s;
      x1 = cx + 0.5 * (W - left - right) / s;
      y0 = cy - 0.5 * (H - top - bottom) / s;
      y1 = cy + 0.5 * (H - top - bottom) / s;
      sx = sy = s;
    }
  }
  cv::Point px(double x, double y) const
  {
    return cv::Point(static_cast<int>(std::lround(left + (x - x0) * sx)),
                     static_cast<int>(std::lround(H - bottom - (y - y0) * sy)));
  }
  void drawFrame(cv::Mat& img, const std::string& xlabel, const std::string& ylabel, const std::string& title) const
  {
    cv::rectangle(img, cv::Point(left, top), cv::Point(W - right, H - bottom), BLACK, 1);
    const double xs = niceStep(x1 - x0, 8), ys = niceStep(y1 - y0, 8);
    const int prec = xs < 1.0 ? 1 : 0, precy = ys < 1.0 ? 1 : 0;
    for (double x = std::ceil(x0 / xs) * xs; x <= x1; x += xs)
    {
      const cv::Point p = px(x, y0);
      cv::line(img, cv::Point(p.x, H - bottom), cv::Point(p.x, H - bottom + 5), BLACK, 1);
      cv::putText(img, fmt(std::abs(x) < 1e-6 * xs ? 0.0 : x, prec), cv::Point(p.x - 12, H - bottom + 20), cv::FONT_HERSHEY_SIMPLEX, 0.4, BLACK, 1,
                  cv::LINE_AA);
    }
    for (double y = std::ceil(y0 / ys) * ys; y <= y1; y += ys)
    {
      const cv::Point p = px(x0, y);
      cv::line(img, cv::Point(left - 5, p.y), cv::Point(left, p.y), BLACK, 1);
      cv::putText(img, fmt(std::abs(y) < 1e-6 * ys ? 0.0 : y, precy), cv::Point(5, p.y + 4), cv::FONT_HERSHEY_SIMPLEX, 0.4, BLACK, 1, cv::LINE_AA);
    }
    cv::putText(img, xlabel, cv::Point(W / 2 - 40, H - 12), cv::FONT_HERSHEY_SIMPLEX, 0.5, BLACK, 1, cv::LINE_AA);
    cv::putText(img, ylabel, cv::Point(5, top - 10), cv::FONT_HERSHEY_SIMPLEX, 0.5, BLACK, 1, cv::LINE_AA);
    if (!title.empty())
      cv::putText(img, title, cv::Point(left + 150, top - 12), cv::FONT_HERSHEY_SIMPLEX, 0.55, BLACK, 1, cv::LINE_AA);
  }
  void drawScaleBar(cv::Mat& img) const
  {
    const double len = niceStep(x1 - x0, 5);
    const cv::Point a(W - right - 20 - static_cast<int>(len * sx), H - bottom - 20);
    const cv::Point b(W - right - 20, H - bottom - 20);
    cv::line(img, a, b, BLACK, 3);
    cv::putText(img, fmt(len, len < 1.0 ? 1 : 0) + " m", cv::Point(a.x, a.y - 8), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                BLACK, 1, cv::LINE_AA);
  }
};

void drawLegend(cv::Mat& img, const std::vector<std::pair<std::string, cv::Scalar>>& items, int x, int y,
                bool boxes = false)
{
  for (size_t i = 0; i < items.size(); ++i)
  {
    const int yy = y + static_cast<int>(i) * 18;
    if (boxes)
      cv::rectangle(img, cv::Point(x, yy - 8), cv::Point(x + 20, yy + 4), items[i].second, cv::FILLED);
    else
      cv::line(img, cv::Point(x, yy - 2), cv::Point(x + 20, yy - 2), items[i].second, 3);
    cv::putText(img, items[i].first, cv::Point(x + 26, yy + 2), cv::FONT_HERSHEY_SIMPLEX, 0.45, BLACK, 1,
                cv::LINE_AA);
  }
}

cv::Scalar truthColor(int8_t v)
{
  if (v == CELL_UNKNOWN)
    return WHITE;
  if (v >= CELL_OBSTACLE)
    return cv::Scalar(60, 60, 60);
  if (v >= CELL_STEP)
    return cv::Scalar(40, 110, 160);
  return cv::Scalar(235, 235, 235);
}

void drawPolyline(cv::Mat& img, const std::vector<cv::Point>& pts, const cv::Scalar& c, int thickness = 2)
{
  if (pts.size() >= 2)
    cv::polylines(img, std::vector<std::vector<cv::Point>>{pts}, false, c, thickness, cv::LINE_AA);
  if (!pts.empty())
    cv::circle(img, pts.front(), 5, c, 2, cv::LINE_AA);
}
}  // namespace

std::vector<Eigen::Vector3d> positions(const Trajectory& traj)
{
  std::vector<Eigen::Vector3d> p;
  p.reserve(traj.size());
  for (const auto& sp : traj)
    p.push_back(sp.pose.translation());
  return p;
}

cv::Mat plotTopDown(const std::vector<PlotSeries>& series, const Grid* floor_plan, const PlotOptions& o)
{
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& s : series)
    for (const auto& p : s.points)
    {
      x0 = std::min(x0, p[o.axis_h]);
      x1 = std::max(x1, p[o.axis_h]);
      y0 = std::min(y0, p[o.axis_v]);
      y1 = std::max(y1, p[o.axis_v]);
    }
  const bool draw_grid = floor_plan && floor_plan->width > 0 && o.axis_h == 0 && o.axis_v == 1;
  if (draw_grid)
  {
    for (int cy = 0; cy < floor_plan->height; ++cy)
      for (int cx = 0; cx < floor_plan->width; ++cx)
        if (floor_plan->at(cx, cy) != CELL_UNKNOWN)
        {
          const Eigen::Vector2d c = floor_plan->cellCenter(cx, cy);
          x0 = std::min(x0, c.x());
          x1 = std::max(x1, c.x());
          y0 = std::min(y0, c.y());
          y1 = std::max(y1, c.y());
        }
  }
  if (x0 > x1)
    x0 = x1 = y0 = y1 = 0.0;
  cv::Mat img(o.height, o.width, CV_8UC3, WHITE);
  const Axes ax(x0, x1, y0, y1, o.width, o.height, true);
  if (draw_grid)
  {
    const double h = 0.5 * floor_plan->resolution;
    for (int cy = 0; cy < floor_plan->height; ++cy)
      for (int cx = 0; cx < floor_plan->width; ++cx)
      {
        const int8_t v = floor_plan->at(cx, cy);
        if (v == CELL_UNKNOWN)
          continue;
        const Eigen::Vector2d c = floor_plan->cellCenter(cx, cy);
        cv::rectangle(img, ax.px(c.x() - h, c.y() + h), ax.px(c.x() + h, c.y() - h), truthColor(v), cv::FILLED);
      }
  }
  std::vector<std::pair<std::string, cv::Scalar>> legend;
  for (const auto& s : series)
  {
    std::vector<cv::Point> pts;
    for (const auto& p : s.points)
      pts.push_back(ax.px(p[o.axis_h], p[o.axis_v]));
    drawPolyline(img, pts, s.color, &s == &series.front() ? 5 : 2);  // the truth wider, under the rest
    legend.emplace_back(s.name, s.color);
  }
  if (draw_grid)
  {
    legend.emplace_back("obstacle (truth)", truthColor(CELL_OBSTACLE));
    legend.emplace_back("step (truth)", truthColor(CELL_STEP));
  }
  const char names[] = {'x', 'y', 'z'};
  ax.drawFrame(img, std::string(1, names[o.axis_h]) + " [m]", std::string(1, names[o.axis_v]) + " [m]",
               o.title.empty() ? "top-down view" : o.title + " (top-down)");
  ax.drawScaleBar(img);
  drawLegend(img, legend, ax.left + 10, ax.top + 18);
  return img;
}

cv::Mat plotSideView(const std::vector<PlotSeries>& series, const PlotOptions& o)
{
  std::vector<std::vector<std::pair<double, double>>> xy;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& s : series)
  {
    std::vector<std::pair<double, double>> v;
    double d = 0.0;
    // index-aligned series share the first series' distances (so they line up); others use their own
    const bool shared = !xy.empty() && s.points.size() == xy[0].size();
    for (size_t i = 0; i < s.points.size(); ++i)
    {
      if (shared)
        d = xy[0][i].first;
      else if (i > 0)
        d += (s.points[i] - s.points[i - 1]).norm();
      const double h = o.up_sign * s.points[i][o.axis_up];
      v.emplace_back(d, h);
      x0 = std::min(x0, d);
      x1 = std::max(x1, d);
      y0 = std::min(y0, h);
      y1 = std::max(y1, h);
    }
    xy.push_back(v);
  }
  if (x0 > x1)
    x0 = x1 = y0 = y1 = 0.0;
  // heights vary by centimetres: give the height axis at least 0.5 m of range
  if (y1 - y0 < 0.5)
  {
    const double c = 0.5 * (y0 + y1);
    y0 = c - 0.25;
    y1 = c + 0.25;
  }
  cv::Mat img(o.height / 2, o.width, CV_8UC3, WHITE);
  const Axes ax(x0, x1, y0, y1, o.width, o.height / 2, false);
  std::vector<std::pair<std::string, cv::Scalar>> legend;
  for (size_t k = 0; k < series.size(); ++k)
  {
    std::vector<cv::Point> pts;
    for (const auto& p : xy[k])
      pts.push_back(ax.px(p.first, p.second));
    drawPolyline(img, pts, series[k].color, k == 0 ? 5 : 2);
    legend.emplace_back(series[k].name, series[k].color);
  }
  ax.drawFrame(img, "distance along path [m]", "height [m]",
               o.title.empty() ? "side view" : o.title + " (side view)");
  drawLegend(img, legend, ax.left + 10, ax.top + 18);
  return img;
}

cv::Mat plotMapScore(const Grid& gt, const Grid& est, const Eigen::Vector2d& wearer_gt, double radius_m,
                     const Eigen::Isometry2d& T_est_gt, int cell_px, const std::string& title)
{
  if (gt.width <= 0 || gt.height <= 0)
    return cv::Mat(100, 100, CV_8UC3, WHITE);
  // the window: the scoring circle plus 2 m, clipped to the grid
  const double reach = radius_m + 2.0;
  const int x0 = std::max(0, static_cast<int>(std::floor((wearer_gt.x() - reach - gt.origin_x) / gt.resolution)));
  const int y0 = std::max(0, static_cast<int>(std::floor((wearer_gt.y() - reach - gt.origin_y) / gt.resolution)));
  const int x1 = std::min(gt.width - 1, static_cast<int>(std::floor((wearer_gt.x() + reach - gt.origin_x) / gt.resolution)));
  const int y1 = std::min(gt.height - 1, static_cast<int>(std::floor((wearer_gt.y() + reach - gt.origin_y) / gt.resolution)));
  if (x1 < x0 || y1 < y0)
    return cv::Mat(100, 100, CV_8UC3, WHITE);
  const int W = x1 - x0 + 1, H = y1 - y0 + 1;
  if (cell_px <= 0)
    cell_px = std::max(2, std::min(16, 700 / std::max(W, H)));
  const int margin = 30, legend_h = 150;
  cv::Mat img(H * cell_px + 2 * margin + legend_h, std::max(W * cell_px + 2 * margin, 320), CV_8UC3, WHITE);
  const cv::Scalar TP(60, 180, 60), FP(0, 140, 255), FN(40, 40, 220), TN(215, 215, 215), UNK(250, 220, 180);
  for (int cy = y0; cy <= y1; ++cy)
    for (int cx = x0; cx <= x1; ++cx)
    {
      const int8_t g = gt.at(cx, cy);
      const Eigen::Vector2d c = gt.cellCenter(cx, cy);
      cv::Scalar col = truthColor(g);
      if (g != CELL_UNKNOWN && (c - wearer_gt).norm() <= radius_m)
      {
        const Eigen::Vector2d ce = T_est_gt * c;
        const int8_t e = est.atWorld(ce.x(), ce.y());
        if (e == CELL_UNKNOWN)
          col = UNK;
        else if (isObstacle(g))
          col = isObstacle(e) ? TP : FN;
        else
          col = isObstacle(e) ? FP : TN;
      }
      else
        col = col * 0.5 + WHITE * 0.5;
      // grid y up: row y1 at the top of the image
      const int px = margin + (cx - x0) * cell_px, py = margin + (y1 - cy) * cell_px;
      cv::rectangle(img, cv::Rect(px, py, cell_px, cell_px), col, cv::FILLED);
    }
  const double gx = (wearer_gt.x() - gt.origin_x) / gt.resolution - x0;
  const double gy = (wearer_gt.y() - gt.origin_y) / gt.resolution - y0;
  const cv::Point wp(margin + static_cast<int>(std::lround(gx * cell_px)),
                     margin + static_cast<int>(std::lround((H - gy) * cell_px)));
  cv::circle(img, wp, static_cast<int>(radius_m / gt.resolution * cell_px), BLACK, 1, cv::LINE_AA);
  cv::circle(img, wp, 4, cv::Scalar(200, 0, 200), cv::FILLED);
  const int ybar = margin + H * cell_px + 20;
  const int bar = static_cast<int>(std::lround(1.0 / gt.resolution * cell_px));
  cv::line(img, cv::Point(margin, ybar), cv::Point(margin + bar, ybar), BLACK, 3);
  cv::putText(img, "1 m", cv::Point(margin + bar + 6, ybar + 4), cv::FONT_HERSHEY_SIMPLEX, 0.45, BLACK, 1,
              cv::LINE_AA);
  if (!title.empty())
    cv::putText(img, title, cv::Point(margin, 20), cv::FONT_HERSHEY_SIMPLEX, 0.5, BLACK, 1, cv::LINE_AA);
  drawLegend(img,
             {{"TP obstacle found", TP},
              {"FP free marked obstacle", FP},
              {"FN obstacle marked free / not obstacle", FN},
              {"TN free", TN},
              {"unknown in estimate", UNK},
              {"truth outside the radius (obstacle / step)", truthColor(CELL_OBSTACLE) * 0.5 + WHITE * 0.5},
              {"wearer (magenta) and scoring radius", cv::Scalar(200, 0, 200)}},
             margin, ybar + 24, true);
  return img;
}

bool writePng(const std::string& path, const cv::Mat& img, std::string* error)
{
  try
  {
    if (img.empty() || !cv::imwrite(path, img))
    {
      if (error)
        *error = "could not write '" + path + "'";
      return false;
    }
  }
  catch (const cv::Exception& e)
  {
    if (error)
      *error = "could not write '" + path + "': " + e.what();
    return false;
  }
  return true;
}

}  // namespace assistive_eval
