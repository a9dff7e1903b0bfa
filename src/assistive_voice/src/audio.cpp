#include "assistive_voice/audio.h"

#include <cmath>
#include <cstring>
#include <fstream>

namespace assistive_voice
{
namespace
{
uint32_t u32(const unsigned char* p) { return p[0] | (p[1] << 8) | (p[2] << 16) | (uint32_t(p[3]) << 24); }
uint16_t u16(const unsigned char* p) { return p[0] | (p[1] << 8); }
void put32(std::ofstream& o, uint32_t v) { for (int i = 0; i < 4; ++i) o.put(char((v >> (8 * i)) & 0xff)); }
void put16(std::ofstream& o, uint16_t v) { o.put(char(v & 0xff)); o.put(char(v >> 8)); }
}  // namespace

bool readWav(const std::string& path, Audio* out, std::string* err)
{
  auto fail = [&](const std::string& m) { if (err) *err = path + ": " + m; return false; };
  std::ifstream f(path, std::ios::binary);
  if (!f)
    return fail("cannot open");
  std::vector<unsigned char> d((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (d.size() < 12 || std::memcmp(d.data(), "RIFF", 4) || std::memcmp(d.data() + 8, "WAVE", 4))
    return fail("not a RIFF/WAVE file");
  int channels = 0, bits = 0;
  size_t pos = 12;
  while (pos + 8 <= d.size())
  {
    const uint32_t len = u32(&d[pos + 4]);
    const size_t body = pos + 8;
    if (!std::memcmp(&d[pos], "fmt ", 4) && body + 16 <= d.size())
    {
      if (u16(&d[body]) != 1)
        return fail("not PCM");
      channels = u16(&d[body + 2]);
      out->rate = static_cast<int>(u32(&d[body + 4]));
      bits = u16(&d[body + 14]);
    }
    else if (!std::memcmp(&d[pos], "data", 4))
    {
      if (channels < 1 || bits != 16)
        return fail("only 16-bit PCM is read");
      // espeak-ng and sox streams may leave the length at 0 or 0xffffffff: read to the end
      const size_t n = std::min<size_t>(len == 0 || len == 0xffffffffu ? d.size() - body : len, d.size() - body) / (2 * channels);
      out->samples.resize(n);
      for (size_t i = 0; i < n; ++i)
      {
        int s = 0;
        for (int c = 0; c < channels; ++c)
          s += static_cast<int16_t>(u16(&d[body + 2 * (i * channels + c)]));
        out->samples[i] = static_cast<int16_t>(s / channels);
      }
      return true;
    }
    pos = body + len + (len & 1);
  }
  return fail("no data chunk");
}

bool writeWav(const std::string& path, const Audio& a)
{
  std::ofstream o(path, std::ios::binary);
  if (!o)
    return false;
  const uint32_t bytes = static_cast<uint32_t>(a.samples.size() * 2);
  o.write("RIFF", 4);
  put32(o, 36 + bytes);
  o.write("WAVEfmt ", 8);
  put32(o, 16);
  put16(o, 1);
  put16(o, 1);
  put32(o, a.rate);
  put32(o, a.rate * 2);
  put16(o, 2);
  put16(o, 16);
  o.write("data", 4);
  put32(o, bytes);
  o.write(reinterpret_cast<const char*>(a.samples.data()), bytes);
  return bool(o);
}

Audio resample(const Audio& a, int rate)
{
  if (a.rate == rate || a.samples.empty())
  {
    Audio r = a;
    r.rate = rate;
    return r;
  }
  Audio r;
  r.rate = rate;
  const double step = double(a.rate) / rate;
  const size_t n = static_cast<size_t>(a.samples.size() / step);
  r.samples.resize(n);
  for (size_t i = 0; i < n; ++i)
  {
    const double x = i * step;
    const size_t k = static_cast<size_t>(x);
    const double f = x - k;
    const double s0 = a.samples[k], s1 = k + 1 < a.samples.size() ? a.samples[k + 1] : s0;
    r.samples[i] = static_cast<int16_t>(std::lround(s0 + f * (s1 - s0)));
  }
  return r;
}

std::vector<std::string> wavList(const std::string& path)
{
  if (path.size() >= 4 && (path.compare(path.size() - 4, 4, ".wav") == 0 || path.compare(path.size() - 4, 4, ".WAV") == 0))
    return {path};
  std::vector<std::string> out;
  std::ifstream f(path);
  const size_t slash = path.rfind('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  std::string line;
  while (std::getline(f, line))
  {
    const size_t a = line.find_first_not_of(" \t\r");
    if (a == std::string::npos || line[a] == '#')
      continue;
    line = line.substr(a, line.find_last_not_of(" \t\r") - a + 1);
    out.push_back(line[0] == '/' ? line : dir + line);
  }
  return out;
}
}  // namespace assistive_voice
