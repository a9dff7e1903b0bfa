#include <assistive_eval/benchmark.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>

namespace assistive_eval
{
// ------------------------------------------------------------------------------ statistics
double percentile(std::vector<double> v, double q)
{
  if (v.empty())
    return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const double pos = q * (v.size() - 1);
  const size_t i = static_cast<size_t>(pos);
  const double f = pos - i;
  return i + 1 < v.size() ? v[i] * (1 - f) + v[i + 1] * f : v[i];
}

double percentileNearestRank(std::vector<double> v, double q)
{
  if (v.empty())
    return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const size_t rank = std::max<size_t>(1, static_cast<size_t>(std::ceil(q * v.size())));
  return v[std::min(v.size(), rank) - 1];
}

double median(std::vector<double> v) { return percentile(std::move(v), 0.5); }

double mean(const std::vector<double>& v)
{
  if (v.empty())
    return std::numeric_limits<double>::quiet_NaN();
  double s = 0.0;
  for (double x : v)
    s += x;
  return s / v.size();
}

// ------------------------------------------------------------------------------ timing
double threadCpuMs()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

double wallMs()
{
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void Stopwatch::restart()
{
  cpu0_ = threadCpuMs();
  wall0_ = assistive_eval::wallMs();
}
double Stopwatch::cpuMs() const { return threadCpuMs() - cpu0_; }
double Stopwatch::wallMs() const { return assistive_eval::wallMs() - wall0_; }

double medianWallMs(const std::function<void()>& f, int reps)
{
  std::vector<double> t;
  for (int i = 0; i < reps; ++i)
  {
    const Stopwatch sw;
    f();
    t.push_back(sw.wallMs());
  }
  return median(t);
}

// ------------------------------------------------------------------------------ JSON line
std::string jsonNumber(double v, int significant)
{
  if (!std::isfinite(v))
    return "null";
  std::ostringstream os;
  os << std::setprecision(significant) << v;
  return os.str();
}

std::string jsonFixed(double v, int decimals)
{
  if (!std::isfinite(v))
    return "null";
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << v;
  return os.str();
}

JsonLine& JsonLine::add(const std::string& key, const std::string& value)
{
  body_ += (body_.empty() ? "\"" : ", \"") + key + "\": " + value;
  return *this;
}
JsonLine& JsonLine::add(const std::string& key, long long count) { return add(key, std::to_string(count)); }
JsonLine& JsonLine::add(const std::string& key, unsigned long long count) { return add(key, std::to_string(count)); }
JsonLine& JsonLine::add(const std::string& key, bool flag) { return add(key, std::string(flag ? "true" : "false")); }

std::string JsonLine::str() const { return "{" + body_ + "}"; }

// ------------------------------------------------------------------------------ command line
namespace
{
/// The whole of `v` as a long long (no trailing characters).
bool wholeNumber(const std::string& v, long long& out)
{
  size_t used = 0;
  try
  {
    out = std::stoll(v, &used);
  }
  catch (const std::exception&)
  {
    return false;
  }
  return !v.empty() && used == v.size();
}
}  // namespace

CommandLine::CommandLine(std::string program, std::string usage) : program_(std::move(program)), usage_(std::move(usage))
{
}

void CommandLine::addOption(Option o) { options_.push_back(std::move(o)); }

CommandLine& CommandLine::flag(const std::string& name, bool* out, bool value)
{
  addOption({name, false, [out, value](const std::string&) { return *out = value, true; }, ""});
  return *this;
}

CommandLine& CommandLine::text(const std::string& name, std::string* out)
{
  addOption({name, true, [out](const std::string& v) { return *out = v, true; }, ""});
  return *this;
}

namespace
{
/// An option's parser for a whole number in [min, max of T], stored into *out.
template <typename T>
std::function<bool(const std::string&)> wholeNumberInto(T* out, long long min)
{
  return [out, min](const std::string& v) {
    long long n = 0;
    if (!wholeNumber(v, n) || n < min || n > static_cast<long long>(std::numeric_limits<T>::max()))
      return false;
    *out = static_cast<T>(n);
    return true;
  };
}
}  // namespace

CommandLine& CommandLine::count(const std::string& name, long long* out, long long min)
{
  addOption({name, true, wholeNumberInto(out, min), "a whole number >= " + std::to_string(min)});
  return *this;
}
CommandLine& CommandLine::count(const std::string& name, long* out, long min)
{
  addOption({name, true, wholeNumberInto(out, min), "a whole number >= " + std::to_string(min)});
  return *this;
}
CommandLine& CommandLine::count(const std::string& name, int* out, int min)
{
  addOption({name, true, wholeNumberInto(out, min), "a whole number >= " + std::to_string(min)});
  return *this;
}

CommandLine& CommandLine::count(const std::string& name, unsigned long long* out)
{
  addOption({name, true,
             [out](const std::string& v) {
               size_t used = 0;
               if (v.empty() || v[0] == '-')
                 return false;
               try
               {
                 *out = std::stoull(v, &used);
               }
               catch (const std::exception&)
               {
                 return false;
               }
               return used == v.size();
             },
             "a whole number >= 0"});
  return *this;
}

CommandLine& CommandLine::number(const std::string& name, double* out)
{
  addOption({name, true,
             [out](const std::string& v) {
               size_t used = 0;
               double x = 0.0;
               try
               {
                 x = std::stod(v, &used);
               }
               catch (const std::exception&)
               {
                 return false;
               }
               if (used != v.size() || !std::isfinite(x))
                 return false;
               *out = x;
               return true;
             },
             "a number"});
  return *this;
}

CommandLine& CommandLine::sets(Sets* out)
{
  addOption({"--set", true,
             [out](const std::string& v) {
               const size_t eq = v.find('=');
               if (eq == std::string::npos || eq == 0)
                 return false;
               out->emplace_back(v.substr(0, eq), v.substr(eq + 1));
               return true;
             },
             "name=value"});
  return *this;
}

CommandLine& CommandLine::positional(std::string* out, const std::string& what, bool required)
{
  positional_ = out;
  positional_what_ = what;
  positional_required_ = required;
  return *this;
}

CommandLine& CommandLine::positionals(std::vector<std::string>* out, const std::string& what, size_t min_count)
{
  positionals_ = out;
  positional_what_ = what;
  positionals_min_ = min_count;
  return *this;
}

std::vector<std::string> CommandLine::passthrough(int argc, char** argv, const std::vector<std::string>& drop) const
{
  std::vector<std::string> out;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    const auto o = std::find_if(options_.begin(), options_.end(), [&](const Option& x) { return x.name == a; });
    if (o == options_.end())
      continue;  // a positional argument
    const bool dropped = std::find(drop.begin(), drop.end(), a) != drop.end();
    if (!dropped)
      out.push_back(a);
    if (o->takes_value && i + 1 < argc)
    {
      ++i;
      if (!dropped)
        out.push_back(argv[i]);
    }
  }
  return out;
}

int CommandLine::usageError(const std::string& message) const
{
  std::cerr << program_ << ": " << message << "\n" << usage_;
  return 2;
}

int CommandLine::parse(int argc, char** argv) const
{
  bool have_positional = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help")
    {
      std::cout << usage_;
      return 0;
    }
    const auto o = std::find_if(options_.begin(), options_.end(), [&](const Option& x) { return x.name == a; });
    if (o != options_.end())
    {
      if (!o->takes_value)
      {
        o->apply("");
        continue;
      }
      if (i + 1 >= argc)
        return usageError(a + " needs a value");
      const std::string v = argv[++i];
      if (!o->apply(v))
        return usageError(a + ": not " + o->expected + ": '" + v + "'");
    }
    else if (a.size() > 1 && a[0] == '-')
      return usageError("unknown option " + a);
    else if (positionals_)
      positionals_->push_back(a);
    else if (!positional_)
      return usageError("unexpected argument '" + a + "'");
    else if (have_positional)
      return usageError("one " + positional_what_ + " only (got '" + *positional_ + "' and '" + a + "')");
    else
    {
      *positional_ = a;
      have_positional = true;
    }
  }
  if (positional_ && positional_required_ && !have_positional)
    return usageError("no " + positional_what_ + " given");
  if (positionals_ && positionals_->size() < positionals_min_)
    return usageError("no " + positional_what_ + " given");
  return -1;
}
}  // namespace assistive_eval
