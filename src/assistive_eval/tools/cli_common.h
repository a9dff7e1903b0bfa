#pragma once
// Small helpers shared by the evaluation / import CLIs: argument parsing and a progress bar.
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace assistive_eval
{
namespace cli
{
/// A command-line mistake (unknown option, missing or malformed value): the caller prints the
/// message and the usage on stderr and exits with 2.
struct UsageError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/// Runs a CLI's body: a UsageError prints "<program>: <why>" and the usage on stderr (exit 2);
/// any other exception "<program>: error: <why>" after `on_error()` (exit 1).
inline int runMain(const char* program, const char* usage, const std::function<int()>& body,
                   const std::function<void()>& on_error = [] {})
{
  try
  {
    return body();
  }
  catch (const UsageError& e)
  {
    std::cerr << program << ": " << e.what() << "\n" << usage;
    return 2;
  }
  catch (const std::exception& e)
  {
    on_error();
    std::cerr << program << ": error: " << e.what() << "\n";
    return 1;
  }
}

/// "--key value" / "--key=value" options (and "--flag" when `flags` names it) plus positional
/// arguments. "-h" is "--help" when "help" is a flag. Throws UsageError on an unknown option
/// (also a single-dash one such as "-x"; "-" alone and negative numbers are positional) and on a
/// missing value.
struct Args
{
  std::vector<std::string> positional;
  std::map<std::string, std::string> options;

  Args(int argc, char** argv, const std::vector<std::string>& known, const std::vector<std::string>& flags = {})
  {
    bool help_flag = false;
    for (const auto& f : flags)
      help_flag |= (f == "help");
    for (int i = 1; i < argc; ++i)
    {
      const std::string a = argv[i];
      if (a == "-h" && help_flag)
        options["help"] = "1";
      else if (a.size() > 2 && a.rfind("--", 0) == 0)
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
          throw UsageError("unknown option --" + key);
        if (is_flag)
        {
          if (eq != std::string::npos)
            throw UsageError("option --" + key + " takes no value");
          value = "1";
        }
        else if (eq == std::string::npos)
        {
          if (i + 1 >= argc)
            throw UsageError("option --" + key + " needs a value");
          value = argv[++i];
        }
        options[key] = value;
      }
      else if (a.size() > 1 && a[0] == '-' && !(a[1] == '.' || (a[1] >= '0' && a[1] <= '9')))
        throw UsageError("unknown option " + a);
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
    const std::string v = get(k);
    size_t used = 0;
    double x = 0.0;
    try
    {
      x = std::stod(v, &used);
    }
    catch (const std::exception&)
    {
      used = 0;
    }
    if (used == 0 || used != v.size() || !std::isfinite(x))
      throw UsageError("option --" + k + ": not a number: '" + v + "'");
    return x;
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
}  // namespace assistive_eval
