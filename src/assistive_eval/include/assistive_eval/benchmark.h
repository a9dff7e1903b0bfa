#pragma once
// What every benchmark CLI shares (vo_benchmark, obstacles_benchmark, disparity_benchmark,
// planner_benchmark, tactile_benchmark): order statistics of timings, a CPU/wall stopwatch, the
// numbers and the writer of the final JSON line (docs/design.md "Benchmarks"), and the command
// line (options, one positional argument, `--set name=value`, `--help`, usage errors).
// ROS-free (the C++ standard library only); library assistive_eval_core.
#include <functional>
#include <iostream>
#include <string>
#include <utility>
#include <vector>
#include "assistive_common/param_table.h"

namespace assistive_eval
{
// ------------------------------------------------------------------------------ statistics
/// q-quantile (q in [0, 1]) with linear interpolation between the order statistics (NumPy's
/// default); NaN when `v` is empty.
double percentile(std::vector<double> v, double q);
/// Nearest-rank q-quantile: the smallest sample with at least a fraction q of the samples at or
/// below it (no interpolation); NaN when `v` is empty.
double percentileNearestRank(std::vector<double> v, double q);
/// percentile(v, 0.5): the mean of the two middle samples for an even count.
double median(std::vector<double> v);
/// Arithmetic mean; NaN when `v` is empty.
double mean(const std::vector<double>& v);

// ------------------------------------------------------------------------------ timing
/// CPU time of the calling thread (what one core spent on it), ms since an arbitrary start.
double threadCpuMs();
/// Steady wall-clock time, ms since an arbitrary start.
double wallMs();
/// Times a piece of work from construction (or restart()): thread CPU ms and wall ms.
class Stopwatch
{
public:
  Stopwatch() { restart(); }
  void restart();
  double cpuMs() const;   ///< CPU ms of this thread since the start
  double wallMs() const;  ///< wall ms since the start

private:
  double cpu0_ = 0.0, wall0_ = 0.0;
};
/// Median wall ms of `reps` calls of `f` (reps >= 1).
double medianWallMs(const std::function<void()>& f, int reps);

// ------------------------------------------------------------------------------ JSON line
/// A number for JSON with `significant` significant digits (std::setprecision); "null" when not
/// finite.
std::string jsonNumber(double v, int significant = 6);
/// A number for JSON with `decimals` fixed decimals; "null" when not finite.
std::string jsonFixed(double v, int decimals);

/// The last stdout line of a benchmark: one JSON object, keys in the order they are added.
///   JsonLine js;
///   js.add("frames", 120).add("drift_pct", jsonNumber(d, 4)).addNull("peer_ms");
///   std::cout << js.str() << std::endl;   // {"frames": 120, "drift_pct": 1.234, "peer_ms": null}
class JsonLine
{
public:
  /// `value` is written as it is: a number from jsonNumber()/jsonFixed(), "null", "true"...
  JsonLine& add(const std::string& key, const std::string& value);
  JsonLine& add(const std::string& key, const char* value) { return add(key, std::string(value)); }
  JsonLine& add(const std::string& key, long long count);
  JsonLine& add(const std::string& key, int count) { return add(key, static_cast<long long>(count)); }
  JsonLine& add(const std::string& key, long count) { return add(key, static_cast<long long>(count)); }
  JsonLine& add(const std::string& key, unsigned long long count);
  JsonLine& add(const std::string& key, unsigned long count) { return add(key, static_cast<unsigned long long>(count)); }
  JsonLine& add(const std::string& key, bool flag);
  JsonLine& addNull(const std::string& key) { return add(key, std::string("null")); }
  std::string str() const;  ///< {"key": value, ...}

private:
  std::string body_;
};

// ------------------------------------------------------------------------------ command line
/// The command line of a benchmark or evaluation CLI, answered the same way by every one:
/// `-h`/`--help` prints the usage on stdout (exit 0); an unknown option, a missing or malformed
/// value or a surplus argument prints "<program>: <what>" and the usage on stderr (exit 2).
///   CommandLine cl("vo_benchmark", usage);
///   cl.positional(&bag, "bag", true).flag("--no-peer", &peer_on, false).count("--frames", &frames, 0L)
///     .sets(&overrides);
///   if (const int rc = cl.parse(argc, argv); rc >= 0) return rc;
class CommandLine
{
public:
  using Sets = std::vector<std::pair<std::string, std::string>>;

  CommandLine(std::string program, std::string usage);
  /// An option without a value: sets *out = value.
  CommandLine& flag(const std::string& name, bool* out, bool value = true);
  /// An option with any text value.
  CommandLine& text(const std::string& name, std::string* out);
  /// An option with a whole number >= min ("--frames: not a whole number >= 0: 'x'" otherwise).
  CommandLine& count(const std::string& name, long long* out, long long min);
  CommandLine& count(const std::string& name, long* out, long min);
  CommandLine& count(const std::string& name, int* out, int min);
  CommandLine& count(const std::string& name, unsigned long long* out);
  /// An option with a finite number.
  CommandLine& number(const std::string& name, double* out);
  /// `--set name=value`, repeatable; the pairs in the order given (the caller checks the names).
  CommandLine& sets(Sets* out);
  /// The one argument that is not an option, e.g. the bag; `what` names it in messages.
  CommandLine& positional(std::string* out, const std::string& what, bool required);
  /// Instead of positional(): any number (>= `min_count`) of arguments that are not options, e.g.
  /// several bags (bench_set.h runs a benchmark on each).
  CommandLine& positionals(std::vector<std::string>* out, const std::string& what, size_t min_count);
  /// argv without the program, the positional arguments and the options named in `drop` (with
  /// their values): what a set run passes on to the run of one bag. Call after a successful parse().
  std::vector<std::string> passthrough(int argc, char** argv, const std::vector<std::string>& drop) const;

  /// Parses argv. Returns -1 when the program should go on, else its exit code (0 after --help,
  /// 2 after a usage error, already printed).
  int parse(int argc, char** argv) const;
  /// Prints "<program>: <message>" and the usage on stderr; returns 2 (the usage-error exit code).
  int usageError(const std::string& message) const;
  const std::string& program() const { return program_; }

private:
  struct Option
  {
    std::string name;
    bool takes_value = false;
    std::function<bool(const std::string&)> apply;  ///< false: malformed value
    std::string expected;                           ///< e.g. "a whole number >= 0"
  };
  void addOption(Option o);

  std::string program_, usage_;
  std::vector<Option> options_;
  std::string* positional_ = nullptr;
  std::vector<std::string>* positionals_ = nullptr;
  size_t positionals_min_ = 0;
  std::string positional_what_;
  bool positional_required_ = false;
};

/// `--set` overrides applied to a stage's parameters by its table (clamped as the node clamps):
/// prints "<program>: --set: <error>" and returns false at the first bad one; prints each clamp as
/// "<program>: <message>".
template <class P>
bool applySets(const CommandLine& cl, const CommandLine::Sets& sets, P& params)
{
  std::string err;
  std::vector<std::string> clamped;
  if (!assistive_common::applyOverrides(params, sets, &err, &clamped))
  {
    std::cerr << cl.program() << ": --set: " << err << "\n";
    return false;
  }
  for (const std::string& c : clamped)
    std::cerr << cl.program() << ": " << c << "\n";
  return true;
}
}  // namespace assistive_eval
