#pragma once
// For the packages' parameter-table tests: the README's parameter table and the yaml override
// files must agree with the table (param_table.h). ROS-free, standard library only.
#include <cctype>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "assistive_common/param_table.h"

namespace assistive_common
{
/// The README header of a parameter table; every row is one parameter (readmeRows()).
inline std::string readmeHeader()
{
  return "| name | type | default | range | unit | meaning |\n|---|---|---|---|---|---|";
}

/// The README rows of a table, with the defaults of `p` (a default-constructed struct).
template <class P>
std::vector<std::string> readmeRows(const P& p)
{
  // A bound naming a field is written with that field's ROS name.
  std::vector<std::pair<std::string, std::string>> field_names;
  p.forEach([&](const ParamInfo& info, const auto&) { field_names.emplace_back(info.field, info.name); });
  auto rosNames = [&](std::string text) {
    for (const auto& fn : field_names)
      for (size_t at = text.find(fn.first); at != std::string::npos; at = text.find(fn.first, at + 1))
      {
        const size_t end = at + fn.first.size();
        auto ident = [&](size_t i) { return i < text.size() && (std::isalnum(static_cast<unsigned char>(text[i])) || text[i] == '_'); };
        if ((at > 0 && ident(at - 1)) || ident(end))
          continue;
        text.replace(at, fn.first.size(), "`" + fn.second + "`");
        at += fn.second.size() + 1;
      }
    return text;
  };
  std::vector<std::string> rows;
  p.forEach([&](const ParamInfo& info, const auto& v) {
    using T = std::decay_t<decltype(v)>;
    const bool numeric = std::is_same<T, int>::value || std::is_same<T, double>::value;
    std::string def = toText(v);
    if (std::is_same<T, std::string>::value)
      def = def.empty() ? "(empty)" : "`" + def + "`";
    const std::string range = numeric ? "[" + rosNames(info.lo_text) + ", " + rosNames(info.hi_text) + "]" : "-";
    const std::string unit = *info.unit ? info.unit : "-";
    rows.push_back("| `" + std::string(info.name) + "` | " + info.type + " | " + def + " | " + range + " | " + unit +
                   " | " + info.text + " |");
  });
  return rows;
}

/// The names of a table.
template <class P>
std::vector<std::string> names(const P& p)
{
  std::vector<std::string> out;
  p.forEach([&](const ParamInfo& info, const auto&) { out.push_back(info.name); });
  return out;
}

inline std::string slurp(const std::string& path)
{
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// Problems of `readme` against the tables' rows: a row missing or different, or a parameter
/// row ("| `name` | int|double|bool|string |") naming no parameter of any table.
inline std::vector<std::string> checkReadme(const std::string& readme, const std::vector<std::string>& rows,
                                            const std::vector<std::string>& known_names)
{
  std::vector<std::string> errors;
  std::set<std::string> lines;
  std::istringstream in(readme);
  for (std::string l; std::getline(in, l);)
    lines.insert(l);
  for (const std::string& r : rows)
    if (!lines.count(r))
      errors.push_back("README lacks the row (or it differs):\n" + r);
  const std::set<std::string> known(known_names.begin(), known_names.end());
  for (const std::string& l : lines)
  {
    if (l.rfind("| `", 0) != 0)
      continue;
    const size_t end = l.find("` | ", 3);
    if (end == std::string::npos)
      continue;
    const std::string type = l.substr(end + 4, l.find(' ', end + 4) - (end + 4));
    if ((type == "int" || type == "double" || type == "bool" || type == "string") && !known.count(l.substr(3, end - 3)))
      errors.push_back("README documents a parameter that is not in the table: " + l);
  }
  return errors;
}

/// The `key: value` lines of a yaml file: the top level (section empty) or the block under
/// `section:`. Comments, quotes and blank lines are dropped; nested blocks are not followed.
inline std::map<std::string, std::string> yamlSection(const std::string& text, const std::string& section = "")
{
  std::map<std::string, std::string> out;
  std::istringstream in(text);
  bool inside = section.empty();
  for (std::string l; std::getline(in, l);)
  {
    const size_t hash = l.find(" #");
    if (l.rfind("#", 0) == 0)
      continue;
    if (hash != std::string::npos)
      l = l.substr(0, hash);
    while (!l.empty() && (l.back() == ' ' || l.back() == '\r'))
      l.pop_back();
    if (l.find_first_not_of(' ') == std::string::npos)
      continue;
    const bool indented = l[0] == ' ';
    if (!section.empty() && !indented)
    {
      inside = l == section + ":";
      continue;
    }
    if (!inside || (section.empty() && indented))
      continue;
    const size_t start = l.find_first_not_of(' ');
    const size_t colon = l.find(':', start);
    if (colon == std::string::npos)
      continue;
    std::string v = colon + 1 < l.size() ? l.substr(l.find_first_not_of(' ', colon + 1)) : "";
    if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'') && v.back() == v.front())
      v = v.substr(1, v.size() - 2);
    out[l.substr(start, colon - start)] = v;
  }
  return out;
}

/// Problems of yaml overrides against the tables (P1, P2... default-constructed structs): a key
/// no table has, a value that does not parse or lies outside its range, or a value equal to the
/// default (the yaml files carry overrides only). `where` prefixes the messages.
template <class... P>
std::vector<std::string> checkOverrides(const std::map<std::string, std::string>& yaml, const std::string& where,
                                        P... tables)
{
  std::vector<std::string> errors;
  for (const auto& kv : yaml)
  {
    bool found = false;
    auto check = [&](auto p) {
      if (found || !has(p, kv.first))
        return;
      found = true;
      auto changed = p;
      std::string err;
      if (!setFromText(changed, kv.first, kv.second, &err))
      {
        errors.push_back(where + ": " + err);
        return;
      }
      if (describe(changed) == describe(p))
        errors.push_back(where + ": " + kv.first + ": " + kv.second + " is the default (yaml files carry overrides only)");
      if (!clampToTable(changed).empty())
        errors.push_back(where + ": " + kv.first + ": " + kv.second + " is out of range");
    };
    (check(tables), ...);
    if (!found)
      errors.push_back(where + ": " + kv.first + " is not a parameter");
  }
  return errors;
}
/// A package's whole check: the README at `readme_path` holds every row of the tables and no
/// other parameter row; the yaml at `yaml_path` (its block `section`, or the top level when
/// empty) carries only overrides of the tables. On a README problem the expected rows follow,
/// ready to paste.
template <class... P>
std::vector<std::string> checkPackage(const std::string& readme_path, const std::string& yaml_path,
                                      const std::string& section, P... tables)
{
  std::vector<std::string> rows, all_names;
  auto add = [&](const auto& p) {
    const auto r = readmeRows(p);
    const auto n = names(p);
    rows.insert(rows.end(), r.begin(), r.end());
    all_names.insert(all_names.end(), n.begin(), n.end());
  };
  (add(tables), ...);
  const std::string readme = slurp(readme_path);
  std::vector<std::string> errors;
  if (readme.empty())
    errors.push_back("cannot read " + readme_path);
  else
    errors = checkReadme(readme, rows, all_names);
  if (!errors.empty())
  {
    std::string table = readmeHeader();
    for (const std::string& r : rows)
      table += "\n" + r;
    errors.push_back("the expected README table:\n" + table);
  }
  const std::string yaml = slurp(yaml_path);
  if (yaml.empty())
    errors.push_back("cannot read " + yaml_path);
  const auto more = checkOverrides(yamlSection(yaml, section), yaml_path + (section.empty() ? "" : ":" + section), tables...);
  errors.insert(errors.end(), more.begin(), more.end());
  return errors;
}
}  // namespace assistive_common
