#include <assistive_eval/bench_set.h>

#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>

#include <assistive_eval/benchmark.h>

namespace fs = std::filesystem;

namespace assistive_eval
{
namespace
{
void skipSpace(const std::string& s, size_t& i)
{
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i])))
    ++i;
}
/// Reads a JSON string starting at s[i] == '"'; false when malformed.
bool readString(const std::string& s, size_t& i, std::string* out)
{
  if (i >= s.size() || s[i] != '"')
    return false;
  ++i;
  std::string r;
  while (i < s.size() && s[i] != '"')
  {
    if (s[i] == '\\' && i + 1 < s.size())
      ++i;
    r += s[i++];
  }
  if (i >= s.size())
    return false;
  ++i;
  if (out)
    *out = r;
  return true;
}
/// Skips a nested array or object (strings inside respected).
bool skipNested(const std::string& s, size_t& i)
{
  int depth = 0;
  while (i < s.size())
  {
    const char c = s[i];
    if (c == '"')
    {
      if (!readString(s, i, nullptr))
        return false;
      continue;
    }
    if (c == '[' || c == '{')
      ++depth;
    else if (c == ']' || c == '}')
    {
      --depth;
      if (depth == 0)
      {
        ++i;
        return true;
      }
    }
    ++i;
  }
  return false;
}
std::string fmt(double v)
{
  if (!std::isfinite(v))
    return "null";
  std::ostringstream os;
  os << std::setprecision(4) << v;
  return os.str();
}
std::string jsonString(const std::string& s)
{
  std::string o = "\"";
  for (char c : s)
  {
    if (c == '"' || c == '\\')
      o += '\\';
    o += c;
  }
  return o + "\"";
}
std::string toolPath(const std::string& tool)
{
  // Beside this executable in the devel/install space (lib/<package>/<exe>), else rosrun.
  const std::string self = selfExecutable();
  if (!self.empty())
  {
    const fs::path p = fs::path(self).parent_path().parent_path() / "assistive_sim" / tool;
    std::error_code ec;
    if (fs::exists(p, ec))
      return p.string();
  }
  return "";
}
std::vector<std::string> toolCommand(const std::string& tool)
{
  const std::string p = toolPath(tool);
  if (!p.empty())
    return {p};
  return {"rosrun", "assistive_sim", tool};
}
}  // namespace

std::vector<std::string> splitList(const std::string& s)
{
  std::vector<std::string> out;
  std::string cur;
  for (char c : s + ",")
  {
    if (c == ',')
    {
      if (!cur.empty())
        out.push_back(cur);
      cur.clear();
    }
    else if (!std::isspace(static_cast<unsigned char>(c)))
      cur += c;
  }
  return out;
}

bool parseJsonNumbers(const std::string& line, std::map<std::string, double>* out)
{
  size_t i = 0;
  skipSpace(line, i);
  if (i >= line.size() || line[i] != '{')
    return false;
  ++i;
  for (;;)
  {
    skipSpace(line, i);
    if (i < line.size() && line[i] == '}')
      return true;
    std::string key;
    if (!readString(line, i, &key))
      return false;
    skipSpace(line, i);
    if (i >= line.size() || line[i] != ':')
      return false;
    ++i;
    skipSpace(line, i);
    if (i >= line.size())
      return false;
    const char c = line[i];
    if (c == '"')
    {
      if (!readString(line, i, nullptr))
        return false;
    }
    else if (c == '[' || c == '{')
    {
      if (!skipNested(line, i))
        return false;
    }
    else if (line.compare(i, 4, "null") == 0)
    {
      (*out)[key] = std::numeric_limits<double>::quiet_NaN();
      i += 4;
    }
    else if (line.compare(i, 4, "true") == 0)
    {
      (*out)[key] = 1.0;
      i += 4;
    }
    else if (line.compare(i, 5, "false") == 0)
    {
      (*out)[key] = 0.0;
      i += 5;
    }
    else
    {
      const char* b = line.c_str() + i;
      char* e = nullptr;
      const double v = std::strtod(b, &e);
      if (e == b)
        return false;
      (*out)[key] = v;
      i += static_cast<size_t>(e - b);
    }
    skipSpace(line, i);
    if (i < line.size() && line[i] == ',')
    {
      ++i;
      continue;
    }
    if (i < line.size() && line[i] == '}')
      return true;
    return false;
  }
}

std::string lastJsonLine(const std::string& text)
{
  std::istringstream is(text);
  std::string line, last;
  while (std::getline(is, line))
    if (!line.empty() && line[0] == '{')
      last = line;
  return last;
}

double jsonNumber(const std::string& json_line, const std::string& key, double missing)
{
  std::map<std::string, double> values;
  if (!parseJsonNumbers(json_line, &values))
    return missing;
  const auto it = values.find(key);
  return it == values.end() ? missing : it->second;
}

std::string readTextFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string bagStem(const std::string& path)
{
  return fs::path(path).stem().string();
}

std::vector<SetAggregate> aggregateSet(const std::vector<BagResult>& bags, const std::vector<SetFigure>& figures)
{
  std::vector<SetAggregate> out;
  for (const SetFigure& f : figures)
  {
    SetAggregate a;
    a.key = f.key;
    a.mean = a.worst = std::numeric_limits<double>::quiet_NaN();
    double sum = 0.0;
    for (const BagResult& b : bags)
    {
      if (!b.ok)
        continue;
      const auto it = b.values.find(f.key);
      if (it == b.values.end() || !std::isfinite(it->second))
      {
        ++a.missing;
        continue;
      }
      const double v = it->second;
      sum += v;
      // The first bag of equal worst figures keeps the name (stable in the bags' order).
      if (a.n == 0 || (f.higher_is_better ? v < a.worst : v > a.worst))
      {
        a.worst = v;
        a.worst_bag = b.name;
      }
      ++a.n;
    }
    if (a.n > 0)
      a.mean = sum / a.n;
    out.push_back(a);
  }
  return out;
}

std::string setTable(const std::vector<BagResult>& bags, const std::vector<SetFigure>& figures,
                     const std::vector<SetAggregate>& agg)
{
  size_t name_w = 6;
  for (const BagResult& b : bags)
    name_w = std::max(name_w, b.name.size() + 1);
  std::ostringstream os;
  os << std::left << std::setw(static_cast<int>(name_w)) << "bag";
  std::vector<size_t> w;
  for (const SetFigure& f : figures)
  {
    w.push_back(std::max<size_t>(10, f.key.size() + 1));
    os << std::right << std::setw(static_cast<int>(w.back())) << f.key;
  }
  os << "\n";
  for (const BagResult& b : bags)
  {
    os << std::left << std::setw(static_cast<int>(name_w)) << b.name << std::right;
    if (!b.ok)
    {
      os << "  (failed: no result)\n";
      continue;
    }
    for (size_t k = 0; k < figures.size(); ++k)
    {
      const auto it = b.values.find(figures[k].key);
      os << std::setw(static_cast<int>(w[k])) << (it == b.values.end() ? "-" : fmt(it->second));
    }
    os << "\n";
  }
  os << std::left << std::setw(static_cast<int>(name_w)) << "mean" << std::right;
  for (size_t k = 0; k < agg.size(); ++k)
    os << std::setw(static_cast<int>(w[k])) << fmt(agg[k].mean);
  os << "\n" << std::left << std::setw(static_cast<int>(name_w)) << "worst" << std::right;
  for (size_t k = 0; k < agg.size(); ++k)
    os << std::setw(static_cast<int>(w[k])) << fmt(agg[k].worst);
  os << "\n" << std::left << std::setw(static_cast<int>(name_w)) << "(bag)" << std::right;
  for (size_t k = 0; k < agg.size(); ++k)
    os << std::setw(static_cast<int>(w[k])) << (agg[k].worst_bag.empty() ? "-" : agg[k].worst_bag);
  os << "\n";
  return os.str();
}

std::string setJson(const std::vector<BagResult>& bags, const std::vector<SetFigure>& figures,
                    const std::vector<SetAggregate>& agg)
{
  JsonLine js;
  int failed = 0;
  std::string names = "[";
  for (const BagResult& b : bags)
  {
    failed += !b.ok;
    names += (names.size() > 1 ? ", " : "") + jsonString(b.name);
  }
  js.add("bags", static_cast<int>(bags.size())).add("bags_failed", failed).add("bag_names", names + "]");
  for (size_t k = 0; k < figures.size() && k < agg.size(); ++k)
  {
    const SetAggregate& a = agg[k];
    js.add(a.key + "_mean", jsonNumber(a.mean, 6)).add(a.key + "_worst", jsonNumber(a.worst, 6))
        .add(a.key + "_worst_bag", a.worst_bag.empty() ? std::string("null") : jsonString(a.worst_bag));
    if (figures[k].add_max)
      js.add(a.key + "_max", jsonNumber(a.worst, 6));
  }
  return js.str();
}

void SetOptions::addTo(CommandLine& cl)
{
  cl.positionals(&bags, "bag", 0)
      .count("--generated", &generated, 1)
      .text("--kinds", &kinds)
      .flag("--imperfect", &imperfect)
      .text("--keep", &keep);
}

int SetOptions::parse(const CommandLine& cl, int argc, char** argv, const std::function<int()>& run_set,
                      std::string& bag) const
{
  if (const int rc = cl.parse(argc, argv); rc >= 0)
    return rc;
  if (isSet())
    return run_set();
  if (bags.empty())
    return cl.usageError("no bag given");
  bag = bags.front();
  return -1;
}

int runSetFromCommandLine(const CommandLine& cl, int argc, char** argv, const SetOptions& so,
                          const std::vector<SetFigure>& figures, const std::string& per_bag_file_option,
                          const std::string& per_bag_file_value, const std::string& per_bag_file_suffix, long frames,
                          const std::function<void(BagResult&)>& derived)
{
  std::vector<std::string> drop{"--generated", "--kinds", "--imperfect", "--keep"};
  if (!per_bag_file_option.empty())
    drop.push_back(per_bag_file_option);
  const std::vector<std::string> pass = cl.passthrough(argc, argv, drop);
  const std::string self = selfExecutable().empty() ? std::string(argv[0]) : selfExecutable();
  GenerateOptions gen;
  gen.n = so.generated;
  gen.kinds = splitList(so.kinds);
  gen.frames = frames > 0 ? static_cast<int>(frames) : -1;
  gen.imperfect = so.imperfect;
  gen.dir = so.keep;
  gen.keep = !so.keep.empty();
  if (!per_bag_file_value.empty())
  {
    std::error_code ec;
    fs::create_directories(per_bag_file_value, ec);
  }
  const OneBagCommand one = [&](const std::string& bag) {
    std::vector<std::string> a{self, bag};
    a.insert(a.end(), pass.begin(), pass.end());
    if (!per_bag_file_value.empty())
      a.insert(a.end(), {per_bag_file_option,
                         (fs::path(per_bag_file_value) / (bagStem(bag) + per_bag_file_suffix)).string()});
    return a;
  };
  return runBenchmarkSet(cl.program(), so.bags, gen, one, figures, derived);
}

std::string selfExecutable()
{
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : p.string();
}

int runCapture(const std::vector<std::string>& argv, std::string* out)
{
  if (argv.empty())
    return -1;
  int fd[2];
  if (pipe(fd) != 0)
    return -1;
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid < 0)
  {
    close(fd[0]);
    close(fd[1]);
    return -1;
  }
  if (pid == 0)
  {
    dup2(fd[1], STDOUT_FILENO);
    close(fd[0]);
    close(fd[1]);
    std::vector<char*> args;
    for (const std::string& a : argv)
      args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    std::fprintf(stderr, "cannot run %s\n", args[0]);
    _exit(127);
  }
  close(fd[1]);
  char buf[4096];
  ssize_t n;
  while ((n = read(fd[0], buf, sizeof buf)) > 0)
    if (out)
      out->append(buf, static_cast<size_t>(n));
  close(fd[0]);
  int status = 0;
  if (waitpid(pid, &status, 0) < 0)
    return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int runBenchmarkSet(const std::string& program, std::vector<std::string> bags, const GenerateOptions& gen,
                    const OneBagCommand& one_bag, const std::vector<SetFigure>& figures,
                    const std::function<void(BagResult&)>& derived)
{
  std::string dir = gen.dir;
  bool remove_dir = false;
  if (gen.n > 0)
  {
    std::error_code ec;
    if (dir.empty())
    {
      std::string tmpl = (fs::temp_directory_path(ec) / (program + "_set_XXXXXX")).string();
      if (!mkdtemp(tmpl.data()))
      {
        std::cerr << program << ": cannot create a temporary folder\n";
        return 1;
      }
      dir = tmpl;
      remove_dir = !gen.keep;
    }
    fs::create_directories(dir, ec);
    for (int s = 1; s <= gen.n; ++s)
    {
      const std::string stem = (fs::path(dir) / ("gen" + std::to_string(s))).string();
      const std::string world = stem + ".yaml", bag = stem + ".bag";
      if (fs::exists(bag, ec))
      {
        std::cerr << "[" << program << "] set: " << bag << " exists, reused\n";
        bags.push_back(bag);
        continue;
      }
      std::vector<std::string> g = toolCommand("generate_world");
      g.insert(g.end(), {"--seed", std::to_string(s), "--out", world});
      if (!gen.kinds.empty())
        g.insert(g.end(), {"--kind", gen.kinds[static_cast<size_t>(s - 1) % gen.kinds.size()]});
      std::cerr << "[" << program << "] set: generating world " << s << "/" << gen.n << "\n";
      std::string ignored;
      if (runCapture(g, &ignored) != 0)
      {
        std::cerr << program << ": generate_world failed for seed " << s << "\n";
        continue;
      }
      std::vector<std::string> r = toolCommand("render_bag");
      // render_bag's default seed (walk noise, pixel noise), as the shared generated set is rendered:
      // --generated N gives the same bags; the camera errors are drawn from the world's seed.
      r.insert(r.end(), {"--world", world, "--out", bag + ".tmp"});
      if (gen.frames > 0)
        r.insert(r.end(), {"--frames", std::to_string(gen.frames)});
      if (gen.imperfect)
        r.insert(r.end(), {"--imperfect", "--errors-seed", std::to_string(s)});
      std::cerr << "[" << program << "] set: rendering world " << s << "/" << gen.n << "\n";
      if (runCapture(r, &ignored) != 0)
      {
        std::cerr << program << ": render_bag failed for seed " << s << "\n";
        continue;
      }
      fs::rename(bag + ".tmp", bag, ec);
      bags.push_back(bag);
    }
  }
  std::vector<BagResult> results;
  for (size_t k = 0; k < bags.size(); ++k)
  {
    BagResult b;
    b.bag = bags[k];
    b.name = bagStem(bags[k]);
    std::cerr << "[" << program << "] set: bag " << k + 1 << "/" << bags.size() << " " << b.bag << "\n";
    std::string text;
    const int rc = runCapture(one_bag(b.bag), &text);
    b.ok = rc == 0 && parseJsonNumbers(lastJsonLine(text), &b.values);
    if (b.ok && derived)
      derived(b);
    if (!b.ok)
      std::cerr << program << ": " << b.bag << ": no result (exit code " << rc << ")\n";
    results.push_back(b);
  }
  if (remove_dir)
  {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  const std::vector<SetAggregate> agg = aggregateSet(results, figures);
  std::cout << program << " over a set of " << results.size() << " bags"
            << (gen.n > 0 ? " (generated worlds seeds 1.." + std::to_string(gen.n) +
                                (gen.imperfect ? ", camera imperfections" : "") +
                                (gen.keep || !gen.dir.empty() ? ", kept in " + dir : "") + ")"
                          : "")
            << "; mean over the bags that measured a figure, worst bag named\n"
            << setTable(results, figures, agg) << setJson(results, figures, agg) << std::endl;
  const bool any = std::any_of(results.begin(), results.end(), [](const BagResult& b) { return b.ok; });
  return any ? 0 : 1;
}
}  // namespace assistive_eval
