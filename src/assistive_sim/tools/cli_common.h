#pragma once
// Small helpers shared by the evaluation / import CLIs: argument parsing and a progress bar.
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace assistive_sim
{
namespace cli
{
/// "--key value" options (and "--flag" when `flags` names it) plus positional arguments.
struct Args
{
  std::vector<std::string> positional;
  std::map<std::string, std::string> options;

  Args(int argc, char** argv, const std::vector<std::string>& known, const std::vector<std::string>& flags = {})
  {
    for (int i = 1; i < argc; ++i)
    {
      const std::string a = argv[i];
      if (a.size() > 2 && a.rfind("--", 0) == 0)
      {
        std::string key = a.substr(2), value;
        const auto eq = key.find('=');
        if (eq != std::string::npos)
        {
          value = key.substr(eq + 1);
          key = key.substr(0, eq);
        }
        bool is_flag = false;
        for (const auto& f : flags)
          is_flag |= (f == key);
        bool ok = is_flag;
        for (const auto& k : known)
          ok |= (k == key);
        if (!ok)
          throw std::runtime_error("unknown option --" + key);
        if (is_flag)
          value = "1";
        else if (eq == std::string::npos)
        {
          if (i + 1 >= argc)
            throw std::runtime_error("option --" + key + " needs a value");
          value = argv[++i];
        }
        options[key] = value;
      }
      else
        positional.push_back(a);
    }
  }
  bool has(const std::string& k) const { return options.count(k) > 0; }
  std::string get(const std::string& k, const std::string& def = "") const
  {
    const auto it = options.find(k);
    return it == options.end() ? def : it->second;
  }
  double getDouble(const std::string& k, double def) const
  {
    if (!has(k))
      return def;
    try
    {
      return std::stod(get(k));
    }
    catch (const std::exception&)
    {
      throw std::runtime_error("option --" + k + ": not a number: '" + get(k) + "'");
    }
  }
};

/// "[#########.........]  12/60 label" on stderr, redrawn in place.
inline void progress(size_t done, size_t total, const std::string& label)
{
  const int width = 30;
  const int filled = total ? static_cast<int>(width * done / total) : width;
  std::fprintf(stderr, "\r[%s%s] %zu/%zu %s", std::string(static_cast<size_t>(filled), '#').c_str(),
               std::string(static_cast<size_t>(width - filled), '.').c_str(), done, total, label.c_str());
  if (done >= total)
    std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

inline std::string baseName(const std::string& path)
{
  const auto s = path.find_last_of('/');
  std::string b = s == std::string::npos ? path : path.substr(s + 1);
  const auto d = b.rfind('.');
  return d == std::string::npos || d == 0 ? b : b.substr(0, d);
}

}  // namespace cli
}  // namespace assistive_sim
