#include "assistive_slam/map_file.h"
#include <cstring>
#include <fstream>
#include <iterator>
#include <zlib.h>

namespace assistive_slam
{
namespace
{
const char kMagic[8] = {'A', 'S', 'L', 'A', 'M', 'M', 'A', 'P'};

struct Writer
{
  std::string b;
  template <class T>
  void pod(const T& v)
  {
    b.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void pose(const Eigen::Isometry3d& T)
  {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        pod(T.matrix()(r, c));
  }
  void str(const std::string& s)
  {
    pod(static_cast<uint64_t>(s.size()));
    b.append(s);
  }
};

/// Reads the payload; every read is bounds-checked (a bad count cannot run past the end).
struct Reader
{
  const std::string& b;
  size_t i = 0;
  bool ok = true;
  template <class T>
  T pod()
  {
    T v{};
    if (!ok || i + sizeof(T) > b.size())
    {
      ok = false;
      return v;
    }
    std::memcpy(&v, b.data() + i, sizeof(T));
    i += sizeof(T);
    return v;
  }
  Eigen::Isometry3d pose()
  {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        T.matrix()(r, c) = pod<double>();
    return T;
  }
  uint64_t count(size_t min_bytes_each)
  {
    const uint64_t n = pod<uint64_t>();
    if (ok && min_bytes_each > 0 && n > (b.size() - i) / min_bytes_each)
      ok = false;
    return ok ? n : 0;
  }
  std::string str()
  {
    const uint64_t n = count(1);
    if (!ok)
      return {};
    std::string s = b.substr(i, n);
    i += n;
    return s;
  }
};

std::string encode(const MapData& m)
{
  Writer w;
  w.pod(static_cast<uint64_t>(m.keyframes.size()));
  for (const Keyframe& k : m.keyframes)
  {
    w.pod(k.id);
    w.pod(k.submap);
    w.pod(k.stamp);
    w.pose(k.T_odom_cam);
    w.pose(k.T_map_cam);
    w.pod(k.path_m);
    w.pod(static_cast<uint64_t>(k.keypoints.size()));
    const int cols = k.descriptors.empty() ? 0 : k.descriptors.cols;
    w.pod(static_cast<int32_t>(cols));
    for (size_t i = 0; i < k.keypoints.size(); ++i)
    {
      const cv::KeyPoint& p = k.keypoints[i];
      w.pod(p.pt.x);
      w.pod(p.pt.y);
      w.pod(p.size);
      w.pod(p.angle);
      w.pod(static_cast<int32_t>(p.octave));
      w.pod(k.u_right[i]);
      w.pod(k.points[i].x());
      w.pod(k.points[i].y());
      w.pod(k.points[i].z());
      if (cols > 0)
        w.b.append(reinterpret_cast<const char*>(k.descriptors.ptr<uint8_t>(static_cast<int>(i))), cols);
    }
  }
  w.pod(static_cast<uint64_t>(m.submaps.size()));
  for (const SubmapInfo& s : m.submaps)
  {
    w.pod(s.id);
    w.pose(s.T_map_origin);
    w.pod(static_cast<uint64_t>(s.keyframes.size()));
    for (uint32_t k : s.keyframes)
      w.pod(k);
  }
  w.pod(static_cast<uint64_t>(m.loop_links.size()));
  for (const SubmapLinkInfo& l : m.loop_links)
  {
    w.pod(l.from);
    w.pod(l.to);
    w.pose(l.T_from_to);
    for (int i = 0; i < 36; ++i)
      w.pod(l.covariance(i / 6, i % 6));
  }
  w.pod(static_cast<uint64_t>(m.places.size()));
  for (const Place& p : m.places)
  {
    w.str(p.name);
    w.pod(p.keyframe);
    w.pose(p.T_kf_place);
    w.pod(p.stamp);
  }
  return w.b;
}

bool decode(const std::string& b, MapData& m)
{
  Reader r{b};
  const uint64_t nk = r.count(8);
  for (uint64_t n = 0; n < nk && r.ok; ++n)
  {
    Keyframe k;
    k.id = r.pod<uint32_t>();
    k.submap = r.pod<uint32_t>();
    k.stamp = r.pod<double>();
    k.T_odom_cam = r.pose();
    k.T_map_cam = r.pose();
    k.path_m = r.pod<double>();
    const uint64_t nf = r.count(48);
    const int32_t cols = r.pod<int32_t>();
    if (cols < 0 || cols > 4096)
      r.ok = false;
    if (!r.ok)
      break;
    if (cols > 0)
      k.descriptors.create(static_cast<int>(nf), cols, CV_8U);
    for (uint64_t i = 0; i < nf && r.ok; ++i)
    {
      cv::KeyPoint p;
      p.pt.x = r.pod<float>();
      p.pt.y = r.pod<float>();
      p.size = r.pod<float>();
      p.angle = r.pod<float>();
      p.octave = r.pod<int32_t>();
      k.keypoints.push_back(p);
      k.u_right.push_back(r.pod<float>());
      const double x = r.pod<double>(), y = r.pod<double>(), z = r.pod<double>();
      k.points.emplace_back(x, y, z);
      k.landmark.push_back(-1);
      if (cols > 0)
      {
        if (r.i + cols > b.size())
          r.ok = false;
        else
        {
          std::memcpy(k.descriptors.ptr<uint8_t>(static_cast<int>(i)), b.data() + r.i, cols);
          r.i += cols;
        }
      }
    }
    m.keyframes.push_back(std::move(k));
  }
  const uint64_t ns = r.count(8);
  for (uint64_t n = 0; n < ns && r.ok; ++n)
  {
    SubmapInfo s;
    s.id = r.pod<uint32_t>();
    s.T_map_origin = r.pose();
    const uint64_t nkf = r.count(4);
    for (uint64_t i = 0; i < nkf && r.ok; ++i)
      s.keyframes.push_back(r.pod<uint32_t>());
    m.submaps.push_back(std::move(s));
  }
  const uint64_t nl = r.count(8);
  for (uint64_t n = 0; n < nl && r.ok; ++n)
  {
    SubmapLinkInfo l;
    l.from = r.pod<uint32_t>();
    l.to = r.pod<uint32_t>();
    l.T_from_to = r.pose();
    for (int i = 0; i < 36; ++i)
      l.covariance(i / 6, i % 6) = r.pod<double>();
    l.loop_closure = true;
    m.loop_links.push_back(l);
  }
  const uint64_t np = r.count(8);
  for (uint64_t n = 0; n < np && r.ok; ++n)
  {
    Place p;
    p.name = r.str();
    p.keyframe = r.pod<uint32_t>();
    p.T_kf_place = r.pose();
    p.stamp = r.pod<double>();
    if (p.keyframe >= m.keyframes.size())
      r.ok = false;  // a place must sit on a stored keyframe
    m.places.push_back(std::move(p));
  }
  return r.ok && r.i == b.size();
}
}  // namespace

MapData exportMap(const SlamSystem& slam)
{
  MapData m;
  // Places first: each sits on a keyframe that exists already, so the keyframes read after hold it.
  for (const auto& pp : slam.places())
    m.places.push_back(pp.first);
  m.keyframes = slam.keyframes(true);
  m.submaps = slam.submaps();
  for (const SubmapLinkInfo& l : slam.links())
    if (l.loop_closure)
      m.loop_links.push_back(l);
  return m;
}

bool saveMapFile(const std::string& path, const MapData& map, std::string* err)
{
  const std::string payload = encode(map);
  const uint32_t crc = static_cast<uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(payload.data()), static_cast<uInt>(payload.size())));
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  const uint32_t version = kMapFileVersion;
  const uint64_t size = payload.size();
  f.write(kMagic, sizeof(kMagic));
  f.write(reinterpret_cast<const char*>(&version), sizeof(version));
  f.write(reinterpret_cast<const char*>(&size), sizeof(size));
  f.write(payload.data(), static_cast<std::streamsize>(payload.size()));
  f.write(reinterpret_cast<const char*>(&crc), sizeof(crc));
  f.close();
  if (!f)
  {
    if (err)
      *err = "cannot write the map file " + path;
    return false;
  }
  return true;
}

bool loadMapFile(const std::string& path, MapData& map, std::string* err)
{
  auto fail = [&](const std::string& why) {
    if (err)
      *err = "map file " + path + ": " + why;
    return false;
  };
  std::ifstream f(path, std::ios::binary);
  if (!f)
    return fail("cannot be opened");
  const std::string all((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const size_t head = sizeof(kMagic) + sizeof(uint32_t) + sizeof(uint64_t);
  if (all.size() < sizeof(kMagic) || std::memcmp(all.data(), kMagic, sizeof(kMagic)) != 0)
    return fail("not an assistive_slam map file (no ASLAMMAP header)");
  if (all.size() < head)
    return fail("truncated (header incomplete)");
  uint32_t version = 0;
  uint64_t size = 0;
  std::memcpy(&version, all.data() + sizeof(kMagic), sizeof(version));
  std::memcpy(&size, all.data() + sizeof(kMagic) + sizeof(version), sizeof(size));
  if (version != kMapFileVersion)
    return fail("version " + std::to_string(version) + ", this build reads version " +
                std::to_string(kMapFileVersion));
  if (all.size() < head + sizeof(uint32_t) || size > all.size() - head - sizeof(uint32_t))
    return fail("truncated (" + std::to_string(all.size()) + " bytes, the header announces " +
                std::to_string(head + size + sizeof(uint32_t)) + ")");
  if (all.size() != head + size + sizeof(uint32_t))
    return fail("corrupted (" + std::to_string(all.size() - head - size - sizeof(uint32_t)) +
                " bytes after the checksum)");
  const std::string payload = all.substr(head, size);
  uint32_t crc_file = 0;
  std::memcpy(&crc_file, all.data() + head + size, sizeof(crc_file));
  const uint32_t crc = static_cast<uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(payload.data()), static_cast<uInt>(payload.size())));
  if (crc != crc_file)
    return fail("corrupted (checksum mismatch)");
  MapData m;
  if (!decode(payload, m))
    return fail("corrupted (the contents do not parse)");
  map = std::move(m);
  return true;
}

}  // namespace assistive_slam
