#pragma once
// One parameter table per package (rtabmap's Parameters.h is the model). A package lists each
// parameter ONCE, as a row of an X-macro:
//
//   #define MY_PARAMS(X)  (one row per line, each line ending in a backslash)
//     X(double, min_depth, "min_depth", 0.3, 0.05, 10.0, "m", "closer points are dropped")
//     X(double, max_depth, "max_depth", 6.0, min_depth + 0.1, 50.0, "m", "farther points are dropped")
//   struct MyParams { ASSISTIVE_PARAMS_BODY(MY_PARAMS) };
//
// row = X(type, field, ROS name, default, lo, hi, unit, one line of text); type is int, double,
// bool or std::string (bool and string rows give {} as their range). The initializer the macro
// writes is the only default. A range may name fields declared before it: the bounds are
// evaluated on the struct, field by field, so clamp() sees the earlier fields already clamped.
// From the same rows come: the struct, clamp() (the core's and the nodelet's one clamp),
// set() (the benchmarks' `--set name=value`), the nodelet's reader (ros_params.h) and the README
// table with its test (doc_check.h). ROS-free: the cores include it.
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace assistive_common
{
/// What the table says about one parameter.
struct ParamInfo
{
  const char* name;     ///< ROS parameter name, also the benchmarks' --set name
  const char* field;    ///< the struct field
  const char* type;     ///< "int", "double", "bool" or "string"
  const char* lo_text;  ///< the range as written in the table (may name other fields)
  const char* hi_text;
  double lo, hi;        ///< the range evaluated on the struct (numbers only)
  const char* unit;     ///< "" when unitless
  const char* text;     ///< one line of text
};

/// A bound of the table (a bool or string row writes {}: no range).
constexpr double bound(double v) { return v; }

template <typename T>
constexpr const char* typeName()
{
  static_assert(std::is_same<T, int>::value || std::is_same<T, double>::value || std::is_same<T, bool>::value ||
                    std::is_same<T, std::string>::value,
                "parameter tables hold int, double, bool or std::string");
  return std::is_same<T, int>::value ? "int" : std::is_same<T, double>::value ? "double" :
                                                 std::is_same<T, bool>::value ? "bool" : "string";
}

/// The value as the README and the logs write it (bool as true/false, numbers as %g).
template <typename T>
std::string toText(const T& v)
{
  std::ostringstream s;
  if constexpr (std::is_same<T, bool>::value)
    s << (v ? "true" : "false");
  else
    s << v;
  return s.str();
}

/// Parses `text` into `v` (whole text; bool: true/false/1/0; int: a whole number). False if it
/// does not parse; `v` is then unchanged.
template <typename T>
bool fromText(const std::string& text, T& v)
{
  if constexpr (std::is_same<T, std::string>::value)
  {
    v = text;
    return true;
  }
  else if constexpr (std::is_same<T, bool>::value)
  {
    if (text == "true" || text == "1")
      v = true;
    else if (text == "false" || text == "0")
      v = false;
    else
      return false;
    return true;
  }
  else
  {
    char* end = nullptr;
    const double d = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || std::isnan(d))
      return false;
    if (std::is_same<T, int>::value &&
        (d != std::floor(d) || d < std::numeric_limits<int>::min() || d > std::numeric_limits<int>::max()))
      return false;
    v = static_cast<T>(d);
    return true;
  }
}

/// Clamps one value into [info.lo, info.hi] (NaN -> lo); appends a message when it changed it.
template <typename T>
void clampValue(const ParamInfo& info, T& v, std::vector<std::string>& msgs)
{
  if constexpr (std::is_same<T, int>::value || std::is_same<T, double>::value)
  {
    const double x = static_cast<double>(v);
    if (x >= info.lo && x <= info.hi)
      return;
    const T c = static_cast<T>(x > info.hi ? info.hi : info.lo);  // NaN fails both tests: lo
    msgs.push_back(std::string(info.name) + " = " + toText(v) + " out of [" + info.lo_text + ", " + info.hi_text +
                   "] = [" + toText(info.lo) + ", " + toText(info.hi) + "], using " + toText(c));
    v = c;
  }
  else
  {
    (void)info, (void)v, (void)msgs;
  }
}

/// Clamps every numeric parameter of `p` into its table range, in table order; one message per
/// change (the caller logs them).
template <class P>
std::vector<std::string> clampToTable(P& p)
{
  std::vector<std::string> msgs;
  p.forEach([&](const ParamInfo& info, auto& v) { clampValue(info, v, msgs); });
  return msgs;
}

/// True if `name` is a parameter of the table.
template <class P>
bool has(const P& p, const std::string& name)
{
  bool found = false;
  p.forEach([&](const ParamInfo& info, const auto&) { found = found || name == info.name; });
  return found;
}

/// Sets the parameter `name` from text (not clamped). False, with `err`, for an unknown name or
/// a value that does not parse.
template <class P>
bool setFromText(P& p, const std::string& name, const std::string& text, std::string* err = nullptr)
{
  bool found = false, ok = false;
  p.forEach([&](const ParamInfo& info, auto& v) {
    if (!found && name == info.name)
    {
      found = true;
      ok = fromText(text, v);
      if (!ok && err)
        *err = name + ": '" + text + "' is not a valid " + info.type;
    }
  });
  if (!found && err)
    *err = "unknown parameter '" + name + "'";
  return ok;
}

/// (name, value) overrides (the benchmarks' --set), then clampToTable(); the clamp messages are
/// appended to `msgs`. False, with `err`, at the first bad override.
template <class P>
bool applyOverrides(P& p, const std::vector<std::pair<std::string, std::string>>& sets, std::string* err,
                    std::vector<std::string>* msgs = nullptr)
{
  for (const auto& s : sets)
    if (!setFromText(p, s.first, s.second, err))
      return false;
  const std::vector<std::string> c = clampToTable(p);
  if (msgs)
    msgs->insert(msgs->end(), c.begin(), c.end());
  return true;
}

/// The same from "name=value" texts.
template <class P>
bool applyOverrides(P& p, const std::vector<std::string>& sets, std::string* err, std::vector<std::string>* msgs = nullptr)
{
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const std::string& s : sets)
  {
    const size_t eq = s.find('=');
    if (eq == std::string::npos)
    {
      if (err)
        *err = "'" + s + "' is not name=value";
      return false;
    }
    pairs.emplace_back(s.substr(0, eq), s.substr(eq + 1));
  }
  return applyOverrides(p, pairs, err, msgs);
}

/// "name value, name value, ..." of every parameter (for the effective-values log line).
template <class P>
std::string describe(const P& p)
{
  std::string out;
  p.forEach([&](const ParamInfo& info, const auto& v) {
    out += (out.empty() ? "" : ", ") + std::string(info.name) + " " + toText(v);
  });
  return out;
}
}  // namespace assistive_common

// X-macro helpers (see the top of this file).
#define ASSISTIVE_PARAM_FIELD(type, field, name, def, lo, hi, unit, text) type field = def;
#define ASSISTIVE_PARAM_VISIT(type, field, name, def, lo, hi, unit, text)                                          \
  f(::assistive_common::ParamInfo{ name, #field, ::assistive_common::typeName<type>(), #lo, #hi,                           \
                                   ::assistive_common::bound(lo), ::assistive_common::bound(hi), unit, text },                 \
    field);
/// The struct's fields (with their defaults) and forEach(f), which calls f(ParamInfo, field&) for
/// every row in table order.
#define ASSISTIVE_PARAMS_BODY(LIST)                                                                                \
  LIST(ASSISTIVE_PARAM_FIELD)                                                                                      \
  template <class F>                                                                                               \
  void forEach(F&& f)                                                                                              \
  {                                                                                                                \
    LIST(ASSISTIVE_PARAM_VISIT)                                                                                    \
  }                                                                                                                \
  template <class F>                                                                                               \
  void forEach(F&& f) const                                                                                        \
  {                                                                                                                \
    LIST(ASSISTIVE_PARAM_VISIT)                                                                                    \
  }
