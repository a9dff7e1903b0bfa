#pragma once
// A benchmark over a set of bags (issue 17: targets are judged on generated worlds, mean and worst).
// vo_benchmark and obstacles_benchmark take several bags, or `--generated N` (worlds seeds 1..N from
// generate_world, rendered by render_bag), run themselves once per bag (a child process: the
// one-bag run and its output stay exactly as they are), read each run's JSON line, and print
// per-bag rows, the mean and the worst of each figure with the worst bag named, then one JSON line
// with `<key>_mean`, `<key>_worst`, `<key>_worst_bag` (and `<key>_max` for counts where more is
// worse, e.g. free_where_obstacle_cells_max).
// ROS-free (the C++ standard library and POSIX); library assistive_eval_core.
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace assistive_eval
{
/// One figure of a benchmark's JSON line that the set aggregates.
struct SetFigure
{
  std::string key;                ///< the one-bag JSON key, e.g. "recall_3m"
  bool higher_is_better = false;  ///< worst = min if true, else max
  bool add_max = false;           ///< also write `<key>_max` (a count that must stay 0, say)
};

/// The figures of one bag's run: every number of its JSON line (null -> NaN; true/false -> 1/0).
struct BagResult
{
  std::string bag;   ///< path
  std::string name;  ///< short name (file stem), used in tables and `_worst_bag`
  bool ok = false;   ///< the run exited 0 and printed a JSON line
  std::map<std::string, double> values;
};

/// Mean and worst of one figure over the bags that measured it (NaN values are left out and
/// counted in `missing`).
struct SetAggregate
{
  std::string key;
  double mean = 0.0, worst = 0.0;  ///< NaN when no bag measured it
  std::string worst_bag;           ///< name of the worst bag ("" when none)
  int n = 0, missing = 0;
};

/// Numbers of a flat JSON object (one line): numbers, null (NaN), true/false (1/0); strings, arrays
/// and objects are skipped. False when the text is not a JSON object.
bool parseJsonNumbers(const std::string& line, std::map<std::string, double>* out);
/// The last line of `text` that starts with '{' ("" when none).
std::string lastJsonLine(const std::string& text);
/// One number of a JSON line (parseJsonNumbers); `missing` when the key is absent or the line no
/// JSON object: the CLIs' tests read their figures with it.
double jsonNumber(const std::string& json_line, const std::string& key, double missing = -1.0);
/// The whole of a file ("" when it cannot be read): a CLI's captured output.
std::string readTextFile(const std::string& path);
/// "/a/b/gen3.bag" -> "gen3".
std::string bagStem(const std::string& path);

/// Mean and worst of each figure over the bags that ran (failed runs are left out).
std::vector<SetAggregate> aggregateSet(const std::vector<BagResult>& bags, const std::vector<SetFigure>& figures);
/// The readable table: one row per bag, then the mean and the worst (with the worst bag).
std::string setTable(const std::vector<BagResult>& bags, const std::vector<SetFigure>& figures,
                     const std::vector<SetAggregate>& agg);
/// The set's JSON line: bags, bags_failed, then per figure `_mean`, `_worst`, `_worst_bag` (and
/// `_max`), in the order of `figures`.
std::string setJson(const std::vector<BagResult>& bags, const std::vector<SetFigure>& figures,
                    const std::vector<SetAggregate>& agg);

/// How to make a generated set: worlds seeds 1..n, rendered into `dir`.
struct GenerateOptions
{
  int n = 0;
  std::vector<std::string> kinds;  ///< cycled over the seeds; empty: the generator picks by seed
  int frames = -1;                 ///< render_bag --frames (-1: the whole walk)
  bool imperfect = false;          ///< render_bag --imperfect (random camera errors from the seed)
  std::string dir;                 ///< output folder ("": a fresh temporary folder)
  bool keep = false;               ///< keep `dir` afterwards (a temporary one is removed)
};

/// Runs an argv (no shell) with stdout captured into *out and stderr passed through; returns its
/// exit code (-1 when it could not start or was killed).
int runCapture(const std::vector<std::string>& argv, std::string* out);

/// The one-bag run of a set: argv of the child for one bag.
using OneBagCommand = std::function<std::vector<std::string>(const std::string& bag)>;

/// What a benchmark's main() calls when it was given several bags or --generated: generates (if
/// gen.n > 0) and renders the worlds, runs `one_bag` per bag, prints progress on stderr, the table
/// and the JSON line on stdout. `derived` may add figures computed from a bag's values (e.g. a
/// ratio). Returns the exit code (0 when at least one bag ran, 1 otherwise).
int runBenchmarkSet(const std::string& program, std::vector<std::string> bags, const GenerateOptions& gen,
                    const OneBagCommand& one_bag, const std::vector<SetFigure>& figures,
                    const std::function<void(BagResult&)>& derived = nullptr);

class CommandLine;
/// The set options a benchmark's command line adds (one place for both benchmarks):
///   BAG...  several bags;  --generated N  worlds seeds 1..N;  --kinds K1,K2  cycled over the seeds;
///   --imperfect  render with random camera errors;  --keep DIR  render into DIR and keep it.
struct SetOptions
{
  std::vector<std::string> bags;
  int generated = 0;
  std::string kinds, keep;
  bool imperfect = false;
  /// Adds the positional bags (any number, checked by isSet()/bag()) and the options above.
  void addTo(CommandLine& cl);
  /// True when a set run is asked for (several bags or --generated).
  bool isSet() const { return bags.size() > 1 || generated > 0; }
  /// A one-bag-or-set benchmark's command line (these options added to `cl`): -1 with the one bag
  /// in `bag` when the program runs it; else the exit code: of --help or a usage error (no bag),
  /// or of `run_set()` when a set is asked for.
  int parse(const CommandLine& cl, int argc, char** argv, const std::function<int()>& run_set, std::string& bag) const;
};

/// The set run of a benchmark from its parsed command line: every option except the set options
/// and `per_bag_file_option` is passed on to each bag's run; `per_bag_file_option` (e.g. --plot),
/// when given, names a folder and each bag's run writes `<folder>/<stem><per_bag_file_suffix>`.
/// `frames` (> 0) also shortens the rendered walks of --generated.
int runSetFromCommandLine(const CommandLine& cl, int argc, char** argv, const SetOptions& so,
                          const std::vector<SetFigure>& figures, const std::string& per_bag_file_option,
                          const std::string& per_bag_file_value, const std::string& per_bag_file_suffix, long frames,
                          const std::function<void(BagResult&)>& derived = nullptr);

/// This executable's path (/proc/self/exe), for running itself on one bag.
std::string selfExecutable();
/// Splits "a,b,c" into its non-empty parts.
std::vector<std::string> splitList(const std::string& s);
}  // namespace assistive_eval
