#include <assistive_sim/renderer.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstring>
#include <random>
#include <stdexcept>

#include <embree3/rtcore.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <opencv2/imgproc.hpp>

namespace assistive_sim
{
namespace
{
/// Per-triangle surface data: texture frame, precomputed flat shading.
struct Prim
{
  float o[3];   ///< uv origin (already shifted by the texture offset)
  float tu[3];  ///< m -> u
  float tv[3];  ///< m -> v
  float n[3];   ///< unit normal
  float shade;  ///< ambient + diffuse for the fixed light
  int mat;      ///< texture index; -1 = glass
  float refl;   ///< glass reflectance
};

constexpr int NOISE_BITS = 20;
constexpr uint32_t NOISE_MASK = (1u << NOISE_BITS) - 1;

uint64_t mix64(uint64_t x)
{
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdULL;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ULL;
  x ^= x >> 33;
  return x;
}

/// A single ray from `org` along `dir` between tnear and tfar, not yet hit.
RTCRayHit singleRay(const Eigen::Vector3f& org, const Eigen::Vector3f& dir, float tnear, float tfar)
{
  RTCRayHit rh;
  rh.ray.org_x = org.x();
  rh.ray.org_y = org.y();
  rh.ray.org_z = org.z();
  rh.ray.dir_x = dir.x();
  rh.ray.dir_y = dir.y();
  rh.ray.dir_z = dir.z();
  rh.ray.tnear = tnear;
  rh.ray.tfar = tfar;
  rh.ray.mask = 0xFFFFFFFF;
  rh.ray.flags = 0;
  rh.ray.time = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  return rh;
}
}  // namespace

bool CameraErrors::any() const
{
  return baseline_scale != 0.0 || focal_scale != 0.0 || !right_rotation.isZero() || k1 != 0.0 || k2 != 0.0 ||
         rolling_shutter_s > 0.0 || ae_step > 0.0;
}

CameraErrors CameraErrors::random(uint32_t seed, double* exposure_time_s)
{
  // Ranges: README "Camera imperfections" (sources there). Uniform, independent, from the seed.
  std::mt19937 rng(seed * 2654435761u + 17u);
  auto U = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  CameraErrors e;
  e.baseline_scale = U(-0.01, 0.01);
  e.focal_scale = U(-0.005, 0.005);
  const double rot = 0.1 * M_PI / 180.0;
  e.right_rotation = Eigen::Vector3d(U(-rot, rot), U(-rot, rot), U(-rot, rot));
  e.k1 = U(-0.005, 0.005);
  e.k2 = U(-0.002, 0.002);
  e.rolling_shutter_s = U(0.010, 0.033);
  e.ae_step = U(0.05, 0.20);
  e.ae_interval_s = U(2.0, 8.0);
  const double exposure = U(0.002, 0.012);
  if (exposure_time_s) *exposure_time_s = exposure;
  return e;
}

std::string CameraErrors::json(double exposure_time_s) const
{
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "{\"baseline_scale\": %.6f, \"focal_scale\": %.6f, \"right_rotation_deg\": [%.5f, %.5f, %.5f], "
                "\"k1\": %.6f, \"k2\": %.6f, \"rolling_shutter_ms\": %.3f, \"ae_step\": %.4f, \"ae_interval_s\": %.3f, "
                "\"exposure_time_ms\": %.3f}",
                baseline_scale, focal_scale, right_rotation.x() * 180 / M_PI, right_rotation.y() * 180 / M_PI,
                right_rotation.z() * 180 / M_PI, k1, k2, rolling_shutter_s * 1e3, ae_step, ae_interval_s,
                exposure_time_s * 1e3);
  return buf;
}

struct StereoRenderer::Impl
{
  /// Auto-exposure schedule per camera: step times and the gain level after each (in steps).
  std::vector<double> ae_times[2];
  std::vector<int> ae_levels[2];
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<float> verts;  // xyz
  std::vector<unsigned> tris;
  std::vector<Prim> prims;
  std::vector<TextureTile> textures;
  std::vector<float> noise;
  std::vector<float> radiance;  // W*H scratch
  float sky = 0.75f;
  Eigen::Vector3f light;
  struct GlassRay
  {
    uint32_t idx;
    float t;
    float dx, dy, dz;
    unsigned prim;
  };
  std::vector<GlassRay> pending;  // primary rays that hit glass (capacity kept across frames)
  double texture_offset = 0.0;

  // The pattern projector (issue 35): the dots' directions in its frame (z forward, x right), the
  // scene's ambient light, and this frame's lit dots (world point, peak radiance).
  std::vector<Eigen::Vector3f> dot_dirs;
  double ambient_lux = 300.0;
  struct LitDot
  {
    Eigen::Vector3f p;
    float peak;
  };
  std::vector<LitDot> lit_dots;

  /// Casts every dot from the projector at `origin` (world) with rotation `R` (its frame to the
  /// world): the first opaque surface takes it (glass lets the infrared through), shadowing what
  /// lies behind. Keeps the dots bright enough to matter.
  void castDots(const Eigen::Vector3f& origin, const Eigen::Matrix3f& R, const ProjectorParams& pp)
  {
    lit_dots.clear();
    const float scale = static_cast<float>(pp.power * pp.reference_lux / ambient_lux);
    const float max_r = static_cast<float>(pp.max_range);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (const Eigen::Vector3f& d0 : dot_dirs)
    {
      const Eigen::Vector3f dir = R * d0;
      const float tfar = max_r / dir.norm();  // (the ray's parameter runs along the unnormalised dir)
      float tnear = 0.f;
      for (int pass = 0; pass < 4; ++pass)
      {
        RTCRayHit rh = singleRay(origin, dir, tnear, tfar);
        intersect1(&ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
        const Prim& p = prim(rh.hit.geomID, rh.hit.primID);
        const float t = rh.ray.tfar;
        if (p.mat < 0)
        {
          tnear = t * 1.0001f + 1e-4f;  // through the glass
          continue;
        }
        const Eigen::Vector3f h = origin + t * dir;
        const float dist = t * dir.norm();
        const float cosi = std::abs(dir.x() * p.n[0] + dir.y() * p.n[1] + dir.z() * p.n[2]) / dir.norm();
        const float albedo = shadeHit(p, h.x(), h.y(), h.z(), 1e-3f) / std::max(p.shade, 1e-3f);
        const float peak = scale * albedo * cosi / (dist * dist);
        if (peak > 1e-3f) lit_dots.push_back({h, peak});
        break;
      }
    }
  }

  // People (issue 22): a second scene whose one mesh (geometry id PEOPLE_GEOM) is moved to the
  // frame's time before rendering; rays meet the static scene first, then the people scene up to
  // the static hit. Worlds without people never create it (their images are unchanged).
  static constexpr unsigned PEOPLE_GEOM = 1;
  std::vector<Person> people;
  RTCScene people_scene = nullptr;
  RTCGeometry people_geom = nullptr;
  float* people_vb = nullptr;
  std::vector<float> people_verts;
  std::vector<unsigned> people_tris;
  std::vector<Prim> people_prims;
  bool building_people = false;  // addTri writes the people mesh
  double people_time = std::numeric_limits<double>::quiet_NaN();  // rendered where, NaN: at the stamp
  double people_built_at = std::numeric_limits<double>::quiet_NaN();

  void addTri(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Prim& p)
  {
    std::vector<float>& vs = building_people ? people_verts : verts;
    std::vector<unsigned>& ts = building_people ? people_tris : tris;
    const unsigned base = static_cast<unsigned>(vs.size() / 3);
    for (const auto* v : {&a, &b, &c})
      for (int k = 0; k < 3; ++k) vs.push_back(static_cast<float>((*v)[k]));
    ts.insert(ts.end(), {base, base + 1, base + 2});
    (building_people ? people_prims : prims).push_back(p);
  }

  const Prim& prim(unsigned geom, unsigned id) const { return geom == PEOPLE_GEOM ? people_prims[id] : prims[id]; }

  void intersect16(const int* valid, RTCIntersectContext* ctx, RTCRayHit16* rh) const
  {
    rtcIntersect16(valid, scene, ctx, rh);
    if (people_scene) rtcIntersect16(valid, people_scene, ctx, rh);
  }

  void intersect1(RTCIntersectContext* ctx, RTCRayHit* rh) const
  {
    rtcIntersect1(scene, ctx, rh);
    if (people_scene) rtcIntersect1(people_scene, ctx, rh);
  }

  /// A vertical cylinder (16 or 10 sides, flat top) for a person's body or head, its texture
  /// fixed to the body: the ring starts at the facing `yaw`, the top's texture axes turn with it.
  void addPersonCylinder(const Eigen::Vector2d& c, double r, double z0, double z1, double yaw, int sides, int mat,
                         double off_u, double off_v)
  {
    const Eigen::Vector3d Z(0, 0, 1);
    std::vector<Eigen::Vector3d> ring;
    for (int i = 0; i < sides; ++i)
    {
      const double a = yaw + 2 * M_PI * i / sides;
      ring.emplace_back(c.x() + r * std::cos(a), c.y() + r * std::sin(a), 0.0);
    }
    double u = off_u;
    for (int i = 0; i < sides; ++i)
    {
      const Eigen::Vector3d& a = ring[i];
      const Eigen::Vector3d& b = ring[(i + 1) % sides];
      const double len = (b - a).norm();
      const Eigen::Vector3d tu = (b - a) / len;
      const Eigen::Vector3d n(tu.y(), -tu.x(), 0);
      addQuad(a + Z * z0, b + Z * z0, b + Z * z1, a + Z * z1, n, tu, Z, u, z0 + off_v, mat);
      u += len;
    }
    const Eigen::Vector3d ax(std::cos(yaw), std::sin(yaw), 0), ay(-std::sin(yaw), std::cos(yaw), 0);
    Prim p;
    const Eigen::Vector3d o = Eigen::Vector3d(c.x(), c.y(), 0) - ax * off_u - ay * off_v;
    for (int k = 0; k < 3; ++k)
    {
      p.o[k] = static_cast<float>(o[k]);
      p.tu[k] = static_cast<float>(ax[k]);
      p.tv[k] = static_cast<float>(ay[k]);
      p.n[k] = static_cast<float>(Z[k]);
    }
    p.mat = mat;
    p.refl = 0.f;
    p.shade = 0.5f + 0.5f * std::max(0.f, light.z());
    for (int i = 1; i + 1 < sides; ++i) addTri(ring[0] + Z * z1, ring[i] + Z * z1, ring[i + 1] + Z * z1, p);
  }

  /// Every person's mesh at time t (the same triangle count at every t).
  void buildPeopleMesh(double t)
  {
    people_verts.clear();
    people_tris.clear();
    people_prims.clear();
    building_people = true;
    for (size_t i = 0; i < people.size(); ++i)
    {
      const Person& p = people[i];
      const PersonState st = personAt(p, t);
      const double shoulders = p.height - PERSON_HEAD_HEIGHT;
      const double off_u = std::fmod(i * 2.93, 13.0), off_v = std::fmod(i * 1.71, 7.0);
      addPersonCylinder(st.position, p.radius, 0.0, shoulders, st.yaw, 16, p.material, off_u, off_v);
      addPersonCylinder(st.position, PERSON_HEAD_RADIUS * p.radius, shoulders, p.height, st.yaw, 10, p.material,
                        off_u + 5.0, off_v + 3.0);
    }
    building_people = false;
  }

  /// Move the people scene to time t (no-op without people or when already there).
  void updatePeople(double t)
  {
    if (!people_scene || t == people_built_at) return;
    buildPeopleMesh(t);
    std::copy(people_verts.begin(), people_verts.end(), people_vb);
    rtcUpdateGeometryBuffer(people_geom, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(people_geom);
    rtcCommitScene(people_scene);
    people_built_at = t;
  }

  /// Quad a-b-c-d (planar). `tu`/`tv` unit texture axes, uv = ((p - a) . tu + u0, (p - a) . tv + v0).
  void addQuad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d,
               const Eigen::Vector3d& n, const Eigen::Vector3d& tu, const Eigen::Vector3d& tv, double u0, double v0,
               int mat, float refl = 0.f)
  {
    Prim p;
    const Eigen::Vector3d o = a - tu * u0 - tv * v0;
    for (int k = 0; k < 3; ++k)
    {
      p.o[k] = static_cast<float>(o[k]);
      p.tu[k] = static_cast<float>(tu[k]);
      p.tv[k] = static_cast<float>(tv[k]);
      p.n[k] = static_cast<float>(n[k]);
    }
    p.shade = 0.5f + 0.5f * std::max(0.f, n.cast<float>().dot(light));
    p.mat = mat;
    p.refl = refl;
    addTri(a, b, c, p);
    addTri(a, c, d, p);
  }

  void addSolid(const Solid& s, size_t index)
  {
    const double off_u = std::fmod(index * 3.71, 17.0), off_v = std::fmod(index * 1.37, 11.0);
    const Eigen::Vector3d Z(0, 0, 1);
    if (s.glass)
    {
      const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
      const Eigen::Vector3d ax(c, sn, 0);
      const Eigen::Vector3d A(s.center.x() - ax.x() * s.half.x(), s.center.y() - ax.y() * s.half.x(), 0);
      const Eigen::Vector3d B(s.center.x() + ax.x() * s.half.x(), s.center.y() + ax.y() * s.half.x(), 0);
      const Eigen::Vector3d n(-sn, c, 0);
      addQuad(A + Z * s.z0, B + Z * s.z0, B + Z * s.z1, A + Z * s.z1, n, ax, Z, 0, 0, -1,
              static_cast<float>(s.reflectance));
      return;
    }
    std::vector<Eigen::Vector3d> ring;  // footprint, CCW seen from above
    std::vector<double> ring_u;
    if (s.shape == Solid::BOX)
    {
      const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
      const Eigen::Vector2d ax(c, sn), ay(-sn, c);
      const double hx = s.half.x(), hy = s.half.y();
      for (const auto& q : {Eigen::Vector2d(-hx, -hy), Eigen::Vector2d(hx, -hy), Eigen::Vector2d(hx, hy), Eigen::Vector2d(-hx, hy)})
      {
        const Eigen::Vector2d p = s.center + ax * q.x() + ay * q.y();
        ring.emplace_back(p.x(), p.y(), 0.0);
      }
    }
    else
    {
      const int n = std::max(12, std::min(48, static_cast<int>(s.radius * 80)));
      for (int i = 0; i < n; ++i)
      {
        const double a = 2 * M_PI * i / n;
        ring.emplace_back(s.center.x() + s.radius * std::cos(a), s.center.y() + s.radius * std::sin(a), 0.0);
      }
    }
    // Sides.
    double u = off_u;
    for (size_t i = 0; i < ring.size(); ++i)
    {
      const Eigen::Vector3d& a = ring[i];
      const Eigen::Vector3d& b = ring[(i + 1) % ring.size()];
      const Eigen::Vector3d e = b - a;
      const double len = e.norm();
      if (len < 1e-9) continue;
      const Eigen::Vector3d tu = e / len;
      const Eigen::Vector3d n(tu.y(), -tu.x(), 0);  // outward for a CCW ring
      addQuad(a + Z * s.z0, b + Z * s.z0, b + Z * s.z1, a + Z * s.z1, n, tu, Z, u, s.z0 + off_v, s.material);
      u += len;
    }
    // Top (fan) and bottom when lifted.
    const Eigen::Vector3d X(1, 0, 0), Y(0, 1, 0);
    for (size_t i = 1; i + 1 < ring.size(); ++i)
    {
      Prim p;
      const Eigen::Vector3d o = Eigen::Vector3d(off_u, off_v, 0) * -1.0;
      for (int k = 0; k < 3; ++k)
      {
        p.o[k] = static_cast<float>(o[k]);
        p.tu[k] = static_cast<float>(X[k]);
        p.tv[k] = static_cast<float>(Y[k]);
        p.n[k] = static_cast<float>(Z[k]);
      }
      p.mat = s.material;
      p.refl = 0.f;
      p.shade = 0.5f + 0.5f * std::max(0.f, light.z());
      addTri(ring[0] + Z * s.z1, ring[i] + Z * s.z1, ring[i + 1] + Z * s.z1, p);
      if (s.z0 > 0.005)
      {
        for (int k = 0; k < 3; ++k) p.n[k] = static_cast<float>(-Z[k]);
        p.shade = 0.5f + 0.5f * std::max(0.f, -light.z());
        addTri(ring[0] + Z * s.z0, ring[i + 1] + Z * s.z0, ring[i] + Z * s.z0, p);
      }
    }
  }

  float shadeHit(const Prim& p, const float hx, const float hy, const float hz, float footprint) const
  {
    const float dx = hx - p.o[0], dy = hy - p.o[1], dz = hz - p.o[2];
    const float u = dx * p.tu[0] + dy * p.tu[1] + dz * p.tu[2];
    const float v = dx * p.tv[0] + dy * p.tv[1] + dz * p.tv[2];
    return p.shade * textures[p.mat].sample(u, v, footprint);
  }

  /// Transmitted and reflected rays for the pending glass pixels, 16 at a time.
  /// `row_org`: the camera origin per image row (one entry: the same for all rows).
  void resolveGlass(const std::vector<Eigen::Vector3f>& row_org, float inv_f, float* rad, float* depth, int W,
                    RTCIntersectContext* ctx) const
  {
    auto originOf = [&](uint32_t idx) -> const Eigen::Vector3f& {
      return row_org.size() == 1 ? row_org[0] : row_org[std::min<size_t>(idx / static_cast<uint32_t>(W), row_org.size() - 1)];
    };
    alignas(64) RTCRayHit16 tr, rf;
    alignas(64) int valid[16];
    for (size_t base = 0; base < pending.size(); base += 16)
    {
      const int n = static_cast<int>(std::min<size_t>(16, pending.size() - base));
      for (int i = 0; i < 16; ++i)
      {
        valid[i] = i < n ? -1 : 0;
        const GlassRay& g = pending[base + std::min(i, n - 1)];
        const Eigen::Vector3f& org = originOf(g.idx);
        const Prim& p = prims[g.prim];
        const Eigen::Vector3f dir(g.dx, g.dy, g.dz);
        const Eigen::Vector3f nrm(p.n[0], p.n[1], p.n[2]);
        const Eigen::Vector3f h = org + g.t * dir;
        const Eigen::Vector3f rd = dir - 2.f * dir.dot(nrm) * nrm;
        tr.ray.org_x[i] = org.x();
        tr.ray.org_y[i] = org.y();
        tr.ray.org_z[i] = org.z();
        tr.ray.dir_x[i] = dir.x();
        tr.ray.dir_y[i] = dir.y();
        tr.ray.dir_z[i] = dir.z();
        tr.ray.tnear[i] = g.t * 1.0001f + 1e-4f;
        rf.ray.org_x[i] = h.x();
        rf.ray.org_y[i] = h.y();
        rf.ray.org_z[i] = h.z();
        rf.ray.dir_x[i] = rd.x();
        rf.ray.dir_y[i] = rd.y();
        rf.ray.dir_z[i] = rd.z();
        rf.ray.tnear[i] = 1e-3f;
        for (RTCRayHit16* r : {&tr, &rf})
        {
          r->ray.tfar[i] = std::numeric_limits<float>::infinity();
          r->ray.mask[i] = 0xFFFFFFFF;
          r->ray.flags[i] = 0;
          r->ray.time[i] = 0.f;
          r->hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        }
      }
      intersect16(valid, ctx, &tr);
      intersect16(valid, ctx, &rf);
      for (int i = 0; i < n; ++i)
      {
        const GlassRay& g = pending[base + i];
        const Eigen::Vector3f& org = originOf(g.idx);
        const Prim& gp = prims[g.prim];
        const Eigen::Vector3f dir(g.dx, g.dy, g.dz);
        const float dn = dir.norm();
        // Transmitted.
        float trans, t2;
        if (tr.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID)
        {
          trans = skyRadiance(dir.z() / dn);
          t2 = 0.f;
        }
        else if (prim(tr.hit.geomID[i], tr.hit.primID[i]).mat < 0)
        {
          bool through = false;
          trans = traceSingle(org, dir, g.t * 1.0001f + 1e-4f, inv_f, 1, t2, through);  // another panel
        }
        else
        {
          const Prim& p = prim(tr.hit.geomID[i], tr.hit.primID[i]);
          t2 = tr.ray.tfar[i];
          const float cosi = std::max(std::abs(dir.x() * p.n[0] + dir.y() * p.n[1] + dir.z() * p.n[2]) / dn, 0.05f);
          trans = shadeHit(p, org.x() + t2 * dir.x(), org.y() + t2 * dir.y(), org.z() + t2 * dir.z(),
                           t2 * dn * inv_f / std::sqrt(cosi));
        }
        // Reflected (a glass panel seen in the reflection shows the sky).
        float refl;
        const Eigen::Vector3f rd(rf.ray.dir_x[i], rf.ray.dir_y[i], rf.ray.dir_z[i]);
        if (rf.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID || prim(rf.hit.geomID[i], rf.hit.primID[i]).mat < 0)
        {
          refl = skyRadiance(rd.z() / rd.norm());
        }
        else
        {
          const Prim& p = prim(rf.hit.geomID[i], rf.hit.primID[i]);
          const float tt = rf.ray.tfar[i];
          const float path = g.t * dn + tt * rd.norm();
          refl = shadeHit(p, rf.ray.org_x[i] + tt * rd.x(), rf.ray.org_y[i] + tt * rd.y(),
                          rf.ray.org_z[i] + tt * rd.z(), path * inv_f * 2.f);
        }
        rad[g.idx] = (1.f - gp.refl) * trans + gp.refl * refl;
        depth[g.idx] = t2;
      }
    }
  }

  float skyRadiance(float dz_over_norm) const { return sky * (0.85f + 0.15f * dz_over_norm); }

  /// Radiance and depth (along the ray's parameter) for a single ray; follows glass.
  float traceSingle(const Eigen::Vector3f& org, const Eigen::Vector3f& dir, float tnear, float inv_f, int depth,
                    float& t_out, bool& through_glass) const
  {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh = singleRay(org, dir, tnear, std::numeric_limits<float>::infinity());
    intersect1(&ctx, &rh);
    const float dn = dir.norm();
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
    {
      t_out = 0.f;
      return skyRadiance(dir.z() / dn);
    }
    const Prim& p = prim(rh.hit.geomID, rh.hit.primID);
    const float t = rh.ray.tfar;
    const Eigen::Vector3f h = org + t * dir;
    if (p.mat < 0)
    {
      if (depth > 3)
      {
        t_out = t;
        return sky;
      }
      through_glass = true;
      const Eigen::Vector3f n(p.n[0], p.n[1], p.n[2]);
      float t2 = 0.f;
      bool dummy = false;
      const float trans = traceSingle(org, dir, t * 1.0001f + 1e-4f, inv_f, depth + 1, t2, dummy);
      float tr = 0.f;
      const Eigen::Vector3f rdir = dir - 2.f * dir.dot(n) * n;
      const float refl = traceSingle(h, rdir, 1e-3f, inv_f, 10, tr, dummy);
      t_out = t2;
      return (1.f - p.refl) * trans + p.refl * refl;
    }
    t_out = t;
    const float cosi = std::max(std::abs(dir.x() * p.n[0] + dir.y() * p.n[1] + dir.z() * p.n[2]) / dn, 0.05f);
    return shadeHit(p, h.x(), h.y(), h.z(), t * dn * inv_f / std::sqrt(cosi));
  }
};

StereoRenderer::StereoRenderer(const World& world, const CameraParams& params)
  : impl_(new Impl), params_(params)
{
  Impl& d = *impl_;
  d.light = world.light_dir.cast<float>().normalized();
  d.sky = static_cast<float>(world.sky_brightness);
  d.ambient_lux = world.ambientLux();
  if (params_.projector.enabled)
  {
    // A jittered grid on the projector's image plane (semi-random: unique locally, even density),
    // fixed by the device's pattern seed.
    const ProjectorParams& pp = params_.projector;
    const double f = params_.calib.fx > 0 ? params_.calib.fx : 500.0;
    const double step = pp.spacing_px / f;
    const double tx = std::tan(0.5 * pp.fov_h_deg * M_PI / 180.0), ty = std::tan(0.5 * pp.fov_v_deg * M_PI / 180.0);
    std::mt19937 rng(pp.pattern_seed);
    std::uniform_real_distribution<double> J(-0.45, 0.45);
    for (double y = -ty; y <= ty; y += step)
      for (double x = -tx; x <= tx; x += step)
        d.dot_dirs.emplace_back(static_cast<float>(x + J(rng) * step), static_cast<float>(y + J(rng) * step), 1.f);
  }
  for (const Material& m : world.materials) d.textures.emplace_back(m);

  const Eigen::Vector3d X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
  const Eigen::Vector3d f0(world.floor_min.x(), world.floor_min.y(), 0), f1(world.floor_max.x(), world.floor_min.y(), 0),
      f2(world.floor_max.x(), world.floor_max.y(), 0), f3(world.floor_min.x(), world.floor_max.y(), 0);
  d.addQuad(f0, f1, f2, f3, Z, X, Y, world.floor_min.x(), world.floor_min.y(), world.floor_material);
  if (world.has_ceiling)
  {
    const Eigen::Vector3d h = Z * world.ceiling_height;
    d.addQuad(f0 + h, f3 + h, f2 + h, f1 + h, -Z, X, Y, world.floor_min.x(), world.floor_min.y(), world.ceiling_material);
  }
  for (size_t i = 0; i < world.solids.size(); ++i) d.addSolid(world.solids[i], i);

  d.device = rtcNewDevice("threads=1,set_affinity=0");
  if (!d.device) throw std::runtime_error("Embree: cannot create device");
  d.scene = rtcNewScene(d.device);
  rtcSetSceneFlags(d.scene, RTC_SCENE_FLAG_NONE);
  rtcSetSceneBuildQuality(d.scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geom = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
  const size_t nv = d.verts.size() / 3, nt = d.tris.size() / 3;
  float* vb = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
  std::copy(d.verts.begin(), d.verts.end(), vb);
  unsigned* ib = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
  std::copy(d.tris.begin(), d.tris.end(), ib);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(d.scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(d.scene);

  // People: one dynamic mesh, rebuilt (low quality BVH) whenever the time changes.
  d.people = world.people;
  if (!d.people.empty())
  {
    d.buildPeopleMesh(0.0);
    d.people_scene = rtcNewScene(d.device);
    rtcSetSceneFlags(d.people_scene, RTC_SCENE_FLAG_DYNAMIC);
    rtcSetSceneBuildQuality(d.people_scene, RTC_BUILD_QUALITY_LOW);
    d.people_geom = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(d.people_geom, RTC_BUILD_QUALITY_LOW);
    d.people_vb = static_cast<float*>(rtcSetNewGeometryBuffer(d.people_geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), d.people_verts.size() / 3));
    unsigned* pib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(d.people_geom, RTC_BUFFER_TYPE_INDEX, 0,
                                                                   RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                                   d.people_tris.size() / 3));
    std::copy(d.people_tris.begin(), d.people_tris.end(), pib);
    std::copy(d.people_verts.begin(), d.people_verts.end(), d.people_vb);
    rtcCommitGeometry(d.people_geom);
    rtcAttachGeometryByID(d.people_scene, d.people_geom, Impl::PEOPLE_GEOM);
    rtcCommitScene(d.people_scene);
    d.people_built_at = 0.0;
  }

  // Gaussian noise table (deterministic in the seed); frames use seeded offsets into it.
  d.noise.resize(1u << NOISE_BITS);
  std::mt19937 rng(params_.seed * 7919u + 3u);
  std::normal_distribution<float> N(0.f, static_cast<float>(params_.noise_sigma));
  for (float& v : d.noise) v = N(rng);
  d.radiance.resize(static_cast<size_t>(params_.calib.width) * params_.calib.height);
  d.pending.reserve(d.radiance.size());

  // Auto-exposure steps, one independent schedule per camera (an hour; a step every 0.5-1.5
  // intervals; the level walks +-1, turned back at +-2 steps).
  const CameraErrors& e = params_.errors;
  if (e.ae_step > 0.0 && e.ae_interval_s > 0.0)
    for (int cam = 0; cam < 2; ++cam)
    {
      std::mt19937 ae(params_.seed * 104729u + 7u + static_cast<uint32_t>(cam) * 7919u);
      std::uniform_real_distribution<double> U(0.5, 1.5);
      int level = 0;
      for (double t = e.ae_interval_s * U(ae); t < 3600.0; t += e.ae_interval_s * U(ae))
      {
        const bool up = level <= -2 ? true : level >= 2 ? false : (ae() & 1u);
        level += up ? 1 : -1;
        d.ae_times[cam].push_back(t);
        d.ae_levels[cam].push_back(level);
      }
    }
}

double StereoRenderer::autoExposureGain(int cam, double stamp) const
{
  const CameraErrors& e = params_.errors;
  const auto& times = impl_->ae_times[cam == 0 ? 0 : 1];
  const auto it = std::upper_bound(times.begin(), times.end(), stamp);
  if (it == times.begin()) return 1.0;
  const int level = impl_->ae_levels[cam == 0 ? 0 : 1][static_cast<size_t>(it - times.begin()) - 1];
  return std::pow(1.0 + e.ae_step, level);
}

StereoRenderer::~StereoRenderer()
{
  if (impl_->people_geom) rtcReleaseGeometry(impl_->people_geom);
  if (impl_->people_scene) rtcReleaseScene(impl_->people_scene);
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

size_t StereoRenderer::triangleCount() const { return impl_->prims.size(); }

size_t StereoRenderer::dotCount() const { return impl_->dot_dirs.size(); }

void StereoRenderer::setPeopleTime(double t) { impl_->people_time = t; }

double StereoRenderer::castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const
{
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = singleRay(origin.cast<float>(), dir.cast<float>(), 0.f, std::numeric_limits<float>::infinity());
  impl_->intersect1(&ctx, &rh);
  return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1.0 : rh.ray.tfar;
}

namespace
{
constexpr int TW = 4, TH = 4;  // 16-ray packet tile

// Four lanes of a packet's tile row (GCC vector extensions: SSE2 on x86-64, element-wise IEEE
// operations exactly as the scalar ones; no FMA is formed without -mfma).
typedef float v4f __attribute__((vector_size(16)));
typedef int32_t v4i __attribute__((vector_size(16)));

inline v4f load4f(const float* p)
{
  v4f a;
  std::memcpy(&a, p, sizeof a);
  return a;
}
inline v4i load4i(const int* p)
{
  v4i a;
  std::memcpy(&a, p, sizeof a);
  return a;
}
inline void store4(float* p, v4f a) { std::memcpy(p, &a, sizeof a); }
inline void store4(int* p, v4i a) { std::memcpy(p, &a, sizeof a); }
inline v4f sqrt4(v4f a)
{
#if defined(__SSE2__)
  return reinterpret_cast<v4f>(_mm_sqrt_ps(reinterpret_cast<__m128>(a)));
#else
  return v4f{std::sqrt(a[0]), std::sqrt(a[1]), std::sqrt(a[2]), std::sqrt(a[3])};
#endif
}
inline v4f abs4(v4f a) { return reinterpret_cast<v4f>(reinterpret_cast<v4i>(a) & 0x7fffffff); }
inline v4f max4(v4f a, v4f b) { return a < b ? b : a; }  // std::max(a, b), lane by lane
inline v4f toFloat(v4i a) { return __builtin_convertvector(a, v4f); }
inline v4i truncToInt(v4f a) { return __builtin_convertvector(a, v4i); }

/// Lanes built from four scalars in registers (writing a vector's elements one by one through
/// memory and reading the vector back stalls on store forwarding).
template <class F>
inline v4f lanesF(F f)
{
  return v4f{f(0), f(1), f(2), f(3)};
}
template <class F>
inline v4i lanesI(F f)
{
  return v4i{f(0), f(1), f(2), f(3)};
}

/// The surface data of the prims four lanes hit, lane by lane.
struct PrimLanes
{
  v4f o[3], tu[3], tv[3], n[3], shade;
  const TextureTile* tex[4];

  PrimLanes(const Prim* const p[4], const TextureTile* const t[4])
  {
    for (int j = 0; j < 4; ++j) tex[j] = t[j];
    if (p[0] == p[1] && p[0] == p[2] && p[0] == p[3])
    {
      // The usual case: one surface under all four lanes.
      for (int k = 0; k < 3; ++k)
      {
        o[k] = v4f{} + p[0]->o[k];
        tu[k] = v4f{} + p[0]->tu[k];
        tv[k] = v4f{} + p[0]->tv[k];
        n[k] = v4f{} + p[0]->n[k];
      }
      shade = v4f{} + p[0]->shade;
      return;
    }
    for (int k = 0; k < 3; ++k)
    {
      o[k] = lanesF([&](int j) { return p[j]->o[k]; });
      tu[k] = lanesF([&](int j) { return p[j]->tu[k]; });
      tv[k] = lanesF([&](int j) { return p[j]->tv[k]; });
      n[k] = lanesF([&](int j) { return p[j]->n[k]; });
    }
    shade = lanesF([&](int j) { return p[j]->shade; });
  }
};

/// TextureTile::sample for four lanes, each on its own texture (the same operations).
inline v4f sampleLanes(const TextureTile* const tex[4], v4f u, v4f v, v4f footprint)
{
  // Mostly one texture and one level under all four lanes: their data broadcast, not gathered.
  const bool one_tex = tex[0] == tex[1] && tex[0] == tex[2] && tex[0] == tex[3];
  const v4f inv = one_tex ? v4f{} + tex[0]->invTexel() : lanesF([&](int j) { return tex[j]->invTexel(); });
  const v4i nlev = one_tex ? v4i{} + tex[0]->levelCount() : lanesI([&](int j) { return tex[j]->levelCount(); });
  const v4f q = footprint * inv * 1.189207f;
  v4i l = ((reinterpret_cast<v4i>(q) >> 23) & 0xFF) - 127;
  l = q < 1.0f ? v4i{} : l;
  l = l < nlev ? l : nlev - 1;
  const TextureTile::Level* L[4];
  for (int j = 0; j < 4; ++j) L[j] = &tex[j]->mipLevel(l[j]);
  const bool one_level = L[0] == L[1] && L[0] == L[2] && L[0] == L[3];
  const v4f linv = one_level ? v4f{} + L[0]->inv_texel : lanesF([&](int j) { return L[j]->inv_texel; });
  const v4i mask = one_level ? v4i{} + (L[0]->size - 1) : lanesI([&](int j) { return L[j]->size - 1; });
  const v4f x = u * linv - 0.5f, y = v * linv - 0.5f;
  v4i ix = truncToInt(x), iy = truncToInt(y);
  ix += x < toFloat(ix);  // floor: -1 where truncation went up
  iy += y < toFloat(iy);
  const v4f ax = x - toFloat(ix), ay = y - toFloat(iy);
  const v4i x0 = ix & mask, y0 = iy & mask;
  const v4i x1 = (x0 + 1) & mask, y1 = (y0 + 1) & mask;
  const uint8_t* r0[4];
  const uint8_t* r1[4];
  for (int j = 0; j < 4; ++j)
  {
    r0[j] = L[j]->data + (y0[j] << L[j]->shift);
    r1[j] = L[j]->data + (y1[j] << L[j]->shift);
  }
  const v4i a00 = lanesI([&](int j) { return r0[j][x0[j]]; });
  const v4i a01 = lanesI([&](int j) { return r0[j][x1[j]]; });
  const v4i a10 = lanesI([&](int j) { return r1[j][x0[j]]; });
  const v4i a11 = lanesI([&](int j) { return r1[j][x1[j]]; });
  const v4f top = toFloat(a00) + ax * toFloat(a01 - a00);
  const v4f bot = toFloat(a10) + ax * toFloat(a11 - a10);
  return (top + ay * (bot - top)) * (1.0f / 255.0f);
}

/// Impl::shadeHit for four lanes.
inline v4f shadeHits(const PrimLanes& pl, v4f hx, v4f hy, v4f hz, v4f footprint)
{
  const v4f dx = hx - pl.o[0], dy = hy - pl.o[1], dz = hz - pl.o[2];
  const v4f u = dx * pl.tu[0] + dy * pl.tu[1] + dz * pl.tu[2];
  const v4f v = dx * pl.tv[0] + dy * pl.tv[1] + dz * pl.tv[2];
  return pl.shade * sampleLanes(pl.tex, u, v, footprint);
}
}  // namespace

void StereoRenderer::render(const Eigen::Isometry3d& T_wl, double stamp, uint64_t frame_index, RenderOutput& out,
                            const Eigen::Vector3d& omega, const Eigen::Vector3d& velocity)
{
  Impl& d = *impl_;
  d.updatePeople(std::isnan(d.people_time) ? stamp : d.people_time);
  const StereoCalib& c = params_.calib;
  const CameraErrors& err = params_.errors;
  const int W = c.width, H = c.height;
  if (static_cast<int>(d.radiance.size()) != W * H) d.radiance.resize(static_cast<size_t>(W) * H);
  // The true rig (the bag's calibration stays the nominal c): focal and baseline scaled.
  const double fx_true = c.fx * (1.0 + err.focal_scale), fy_true = c.fy * (1.0 + err.focal_scale);
  const double baseline_true = c.baseline * (1.0 + err.baseline_scale);
  const float ifx = static_cast<float>(1.0 / fx_true), ify = static_cast<float>(1.0 / fy_true);
  const float cx = static_cast<float>(c.cx), cy = static_cast<float>(c.cy);
  const float inv_f = static_cast<float>(2.0 / (fx_true + fy_true));
  const float k1 = static_cast<float>(err.k1), k2 = static_cast<float>(err.k2);
  const bool distorted = k1 != 0.f || k2 != 0.f;
  const double rn = err.right_rotation.norm();
  const Eigen::Matrix3d R_err =
      rn > 0 ? Eigen::AngleAxisd(rn, err.right_rotation / rn).toRotationMatrix() : Eigen::Matrix3d::Identity();

  // Exposure (gain) over time, shared by both cameras.
  const double ev = params_.exposure_variation;
  const double ph = (params_.seed % 97) * 0.1;
  const double gain = params_.gain * (1.0 + ev * std::sin(2 * M_PI * stamp / params_.exposure_period + ph)) *
                      (1.0 + 0.4 * ev * std::sin(2 * M_PI * stamp / (0.37 * params_.exposure_period) + 2 * ph));

  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;

  // Per-row camera rotation and origin: one pose (the stamp's) for a global shutter; for a rolling
  // shutter the pose at the row's exposure time, extrapolated with the body rates (rotation
  // R(t + dt) = R(t) exp([omega] dt), origin + v dt).
  const bool rolling = err.rolling_shutter_s > 0.0 && H > 1;
  std::vector<Eigen::Matrix3f> row_R(rolling ? H : 1);
  std::vector<Eigen::Vector3f> row_org(rolling ? H : 1);

  // The projector's dots land where they land whichever camera looks (the stamp's pose).
  const bool dots = emitter_on_ && params_.projector.enabled && !d.dot_dirs.empty();
  if (dots)
    d.castDots((T_wl * params_.projector.offset).cast<float>(), T_wl.linear().cast<float>(), params_.projector);

  for (int cam = 0; cam < 2; ++cam)
  {
    cv::Mat& img = cam == 0 ? out.left : out.right;
    cv::Mat& depth = cam == 0 ? out.depth_left : out.depth_right;
    img.create(H, W, CV_8UC1);
    depth.create(H, W, CV_32FC1);
    if (cam == 0) out.glass_left.create(H, W, CV_8UC1);
    const Eigen::Vector3d offset(cam == 0 ? 0.0 : baseline_true, 0, 0);
    const Eigen::Matrix3d R_cam = cam == 0 ? Eigen::Matrix3d::Identity() : R_err;
    for (size_t r = 0; r < row_R.size(); ++r)
    {
      Eigen::Matrix3d R_l = T_wl.linear();
      Eigen::Vector3d o_l = T_wl.translation();
      if (rolling)
      {
        const double dt = (static_cast<double>(r) / (H - 1) - 0.5) * err.rolling_shutter_s;
        const Eigen::Vector3d w = omega * dt;
        if (w.norm() > 0) R_l = R_l * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
        o_l += velocity * dt;
      }
      row_R[r] = (R_l * R_cam).cast<float>();
      row_org[r] = (o_l + R_l * offset).cast<float>();
    }
    // In little light the gain is capped and the image darkens (LowLightParams)
    const LowLightParams& ll = params_.low_light;
    const double ll_gain = ll.gainAt(d.ambient_lux);
    const double ll_dim = ll_gain > ll.max_gain ? ll.max_gain / ll_gain : 1.0;
    const float scale = static_cast<float>(255.0 * gain * (err.ae_step > 0.0 ? autoExposureGain(cam, stamp) : 1.0) *
                                           ll_dim);
    float* rad = d.radiance.data();
    d.pending.clear();

    // Each 4x4 tile is one 16-ray packet; its rays are set up and shaded one tile row (4 lanes, one
    // image row) at a time in 4-wide vectors. Every lane does the scalar code's operations in the
    // same order (no FMA, no reassociation), so the images are bit-identical to shading one pixel
    // at a time; only the prim and texel reads are per lane.
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[16];
    alignas(64) v4f ray_x[TH], ray_y[TH];
    const v4i lane = {0, 1, 2, 3};
    for (int ty = 0; ty < H; ty += TH)
      for (int tx = 0; tx < W; tx += TW)
      {
        const v4f xs0 = (__builtin_convertvector(tx + lane, v4f) - cx) * ifx;
        const v4i col_ok = tx + lane < W;
        for (int r = 0; r < TH; ++r)
        {
          const int v = ty + r;
          v4f x = xs0, y = v4f{} + (v - cy) * ify;
          if (distorted)
          {
            // Residual distortion: the pixel sees the ray scaled by 1 + k1 r^2 + k2 r^4.
            const v4f r2 = x * x + y * y, s = 1.f + r2 * (k1 + k2 * r2);
            x *= s;
            y *= s;
          }
          ray_x[r] = x;
          ray_y[r] = y;
          const size_t row = rolling ? static_cast<size_t>(std::min(v, H - 1)) : 0;
          const Eigen::Matrix3f& R = row_R[row];
          const Eigen::Vector3f& org = row_org[row];
          const int o = 4 * r;
          store4(valid + o, v < H ? col_ok : v4i{});
          store4(rh.ray.org_x + o, v4f{} + org.x());
          store4(rh.ray.org_y + o, v4f{} + org.y());
          store4(rh.ray.org_z + o, v4f{} + org.z());
          store4(rh.ray.dir_x + o, R(0, 0) * x + R(0, 1) * y + R(0, 2));
          store4(rh.ray.dir_y + o, R(1, 0) * x + R(1, 1) * y + R(1, 2));
          store4(rh.ray.dir_z + o, R(2, 0) * x + R(2, 1) * y + R(2, 2));
          store4(rh.ray.tnear + o, v4f{});
          store4(rh.ray.tfar + o, v4f{} + std::numeric_limits<float>::infinity());
          store4(reinterpret_cast<int*>(rh.ray.mask + o), v4i{} - 1);
          store4(reinterpret_cast<int*>(rh.ray.flags + o), v4i{});
          store4(rh.ray.time + o, v4f{});
          store4(reinterpret_cast<int*>(rh.hit.geomID + o), v4i{} + static_cast<int>(RTC_INVALID_GEOMETRY_ID));
        }
        d.intersect16(valid, &ctx, &rh);
        for (int r = 0; r < TH && ty + r < H; ++r)
        {
          const int v = ty + r, o = 4 * r;
          const v4f dx = load4f(rh.ray.dir_x + o), dy = load4f(rh.ray.dir_y + o), dz = load4f(rh.ray.dir_z + o);
          const v4f x = ray_x[r], y = ray_y[r];
          const v4f dn = sqrt4(1.f + x * x + y * y);
          const v4i geom = load4i(reinterpret_cast<const int*>(rh.hit.geomID + o));
          const v4i hit = geom != static_cast<int>(RTC_INVALID_GEOMETRY_ID);
          const v4f t = hit ? load4f(rh.ray.tfar + o) : v4f{};
          v4f rad4 = d.sky * (0.85f + 0.15f * (dz / dn));  // sky (skyRadiance), replaced where a ray hit
          v4i glass = {};
          // The prims the lanes hit, their textures as the lanes' own (non-hit lanes borrow one).
          const Prim* pp[4];
          const TextureTile* pt[4];
          int textured = 0, first = -1;
          for (int j = 0; j < 4; ++j)
          {
            if (!hit[j] || tx + j >= W) continue;
            const Prim& p = d.prim(static_cast<unsigned>(geom[j]), rh.hit.primID[o + j]);
            if (p.mat < 0)
            {
              // Through glass: traced afterwards in packets (transmitted + reflected rays).
              d.pending.push_back({static_cast<uint32_t>(static_cast<size_t>(v) * W + tx + j), t[j], dx[j], dy[j],
                                   dz[j], rh.hit.primID[o + j]});
              glass[j] = -1;
              continue;
            }
            pp[j] = &p;
            pt[j] = &d.textures[p.mat];
            textured |= 1 << j;
            if (first < 0) first = j;
          }
          if (textured)
          {
            for (int j = 0; j < 4; ++j)
              if (!(textured >> j & 1)) pp[j] = pp[first], pt[j] = pt[first];
            const PrimLanes pl(pp, pt);
            const Eigen::Vector3f& org = row_org[rolling ? static_cast<size_t>(v) : 0];
            const v4f cosi = max4(abs4(dx * pl.n[0] + dy * pl.n[1] + dz * pl.n[2]) / dn, v4f{} + 0.05f);
            const v4f hx = org.x() + t * dx, hy = org.y() + t * dy, hz = org.z() + t * dz;
            const v4f shaded = shadeHits(pl, hx, hy, hz, t * dn * inv_f / sqrt4(cosi));
            const v4i tex_lane = ((v4i{} + textured) >> lane & 1) != 0;
            rad4 = tex_lane ? shaded : rad4;
          }
          rad4 = glass ? v4f{} : rad4;
          const size_t idx = static_cast<size_t>(v) * W + tx;
          float* drow = depth.ptr<float>(v) + tx;
          uint8_t* grow = cam == 0 ? out.glass_left.ptr<uint8_t>(v) + tx : nullptr;
          if (tx + TW <= W)
          {
            store4(rad + idx, rad4);
            store4(drow, t);
            if (grow)
              for (int j = 0; j < 4; ++j) grow[j] = glass[j] ? 255 : 0;
          }
          else
            for (int j = 0; tx + j < W; ++j)
            {
              rad[idx + j] = rad4[j];
              drow[j] = t[j];
              if (grow) grow[j] = glass[j] ? 255 : 0;
            }
        }
      }

    if (!d.pending.empty()) d.resolveGlass(row_org, inv_f, rad, depth.ptr<float>(), W, &ctx);
    d.pending.clear();

    if (dots)
    {
      // Each lit dot as this camera sees it: a small Gaussian where its point projects, when the
      // surface the pixel shows is the dot's own (not hidden from this camera by something nearer).
      // (the middle row's pose under a rolling shutter; residual distortion is left out: the dots
      // land within a fraction of a pixel of where the distorted image would put them)
      const Eigen::Matrix3f& R = row_R[row_R.size() / 2];
      const Eigen::Vector3f& org = row_org[row_org.size() / 2];
      const float fx = static_cast<float>(fx_true), fy = static_cast<float>(fy_true);
      const float sig = static_cast<float>(params_.projector.dot_sigma_px);
      const float inv2s2 = 1.f / (2.f * sig * sig);
      const int rad_px = std::max(1, static_cast<int>(std::ceil(2.5f * sig)));
      const float* dep = depth.ptr<float>();
      for (const Impl::LitDot& ld : d.lit_dots)
      {
        const Eigen::Vector3f pc = R.transpose() * (ld.p - org);
        if (pc.z() < 0.05f) continue;
        const float u = fx * pc.x() / pc.z() + cx, v = fy * pc.y() / pc.z() + cy;
        const int ui = static_cast<int>(std::lround(u)), vi = static_cast<int>(std::lround(v));
        if (ui < 0 || vi < 0 || ui >= W || vi >= H) continue;
        const float z_seen = dep[static_cast<size_t>(vi) * W + ui];
        if (!(z_seen > 0.f) || pc.z() > z_seen * 1.03f + 0.02f) continue;
        for (int dv = -rad_px; dv <= rad_px; ++dv)
          for (int du = -rad_px; du <= rad_px; ++du)
          {
            const int x = ui + du, y = vi + dv;
            if (x < 0 || y < 0 || x >= W || y >= H) continue;
            const float ex = static_cast<float>(x) - u, ey = static_cast<float>(y) - v;
            rad[static_cast<size_t>(y) * W + x] += ld.peak * std::exp(-(ex * ex + ey * ey) * inv2s2);
          }
      }
    }

    // Motion blur: a line kernel along the image motion of the principal point during the exposure.
    if (params_.exposure_time > 0.0)
    {
      const double du = -c.fx * omega.y() * params_.exposure_time;
      const double dv = c.fy * omega.x() * params_.exposure_time;
      const double len = std::hypot(du, dv);
      if (len > 0.7)
      {
        const int k = 2 * static_cast<int>(std::ceil(len / 2)) + 1;
        cv::Mat kernel = cv::Mat::zeros(k, k, CV_32F);
        const int steps = 4 * k;
        for (int s = 0; s <= steps; ++s)
        {
          const double a = static_cast<double>(s) / steps - 0.5;
          const int px = static_cast<int>(std::lround(k / 2 + a * du));
          const int py = static_cast<int>(std::lround(k / 2 + a * dv));
          kernel.at<float>(std::clamp(py, 0, k - 1), std::clamp(px, 0, k - 1)) += 1.f;
        }
        kernel /= cv::sum(kernel)[0];
        cv::Mat radm(H, W, CV_32F, rad);
        cv::Mat blurred;
        cv::filter2D(radm, blurred, -1, kernel, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
        blurred.copyTo(radm);
      }
    }

    // Quantise with noise.
    const uint32_t off = static_cast<uint32_t>(mix64(params_.seed * 1000003ULL + frame_index * 2 + cam));
    const float* nz = d.noise.data();
    const bool noisy = params_.noise_sigma > 0.0;
    // gain's extra noise: its variance a + b S, drawn from the same table at another offset
    const double g = std::min(ll_gain, ll.max_gain), e_per_grey = ll.full_well_e / 255.0;
    const bool low_light = noisy && g > 1.0;
    const float var_a = static_cast<float>(ll.read_noise_e * ll.read_noise_e * (g * g - 1.0) / (e_per_grey * e_per_grey));
    const float var_b = static_cast<float>((g - 1.0) / e_per_grey);
    const float inv_sigma = noisy ? static_cast<float>(1.0 / params_.noise_sigma) : 0.f;
    const uint32_t off2 = off ^ 0x5bd1e995u;
    for (int v = 0; v < H; ++v)
    {
      uint8_t* row = img.ptr<uint8_t>(v);
      const float* rr = rad + static_cast<size_t>(v) * W;
      const uint32_t base = off + static_cast<uint32_t>(v) * W;
      if (low_light)
      {
        const uint32_t base2 = off2 + static_cast<uint32_t>(v) * W;
        for (int u = 0; u < W; ++u)
        {
          const float sgl = rr[u] * scale;
          const float extra = std::sqrt(var_a + var_b * std::max(sgl, 0.f)) * inv_sigma * nz[(base2 + u) & NOISE_MASK];
          row[u] = static_cast<uint8_t>(std::clamp(sgl + nz[(base + u) & NOISE_MASK] + extra + 0.5f, 0.f, 255.f));
        }
        continue;
      }
      for (int u = 0; u < W; ++u)
      {
        float val = rr[u] * scale + (noisy ? nz[(base + u) & NOISE_MASK] : 0.f) + 0.5f;
        row[u] = static_cast<uint8_t>(std::clamp(val, 0.f, 255.f));
      }
    }
  }
}

}  // namespace assistive_sim
