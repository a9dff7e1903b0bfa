#include "assistive_voice/commands.h"

#include <cctype>
#include <sstream>

namespace assistive_voice
{
const char* actionName(Action a)
{
  switch (a)
  {
    case Action::SAVE_PLACE: return "save_place";
    case Action::GUIDE_BACK: return "guide_back";
    case Action::TOGGLE_PAUSE: return "toggle_pause";
    case Action::PAUSE: return "pause";
    case Action::RESUME: return "resume";
    case Action::WHERE_AM_I: return "where_am_i";
    case Action::WHAT_IS_AHEAD: return "what_is_ahead";
    case Action::YES: return "yes";
    case Action::NO: return "no";
    case Action::NONE: break;
  }
  return "none";
}

const std::vector<std::string>& defaultPlaceNames()
{
  // Short, acoustically distinct words of pocketsphinx's dictionary.
  static const std::vector<std::string> names = {"door", "home", "office", "car", "bus stop", "entrance",
                                                 "exit", "desk", "kitchen", "shop", "stairs", "lift"};
  return names;
}

std::string commandGrammar(const std::vector<std::string>& names)
{
  std::ostringstream g;
  g << "#JSGF V1.0;\n"
       "grammar vest;\n"
       "public <command> = <save> | <back> | pause | resume | where am i | what is ahead;\n"
       "<save> = save place [<name>];\n"
       "<back> = take me back [to [the] <name>];\n"
       "<name> = ";
  for (size_t i = 0; i < names.size(); ++i)
    g << (i ? " | " : "") << names[i];
  g << ";\n";
  return g.str();
}

std::string confirmGrammar()
{
  return "#JSGF V1.0;\ngrammar confirm;\npublic <answer> = yes | no;\n";
}

std::string normalizeText(const std::string& text)
{
  std::istringstream in(text);
  std::string w, out;
  while (in >> w)
  {
    std::string t;
    for (char c : w)
    {
      if (c == '(')
        break;  // pocketsphinx alternate pronunciation: "the(2)"
      if (std::isalnum(static_cast<unsigned char>(c)) || c == '\'')
        t += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    if (t.empty() || w[0] == '<' || w[0] == '[' || w[0] == '+')
      continue;  // fillers: <sil>, <s>, [noise], +breath+
    out += (out.empty() ? "" : " ") + t;
  }
  return out;
}

namespace
{
bool startsWith(const std::string& s, const std::string& p)
{
  return s.size() >= p.size() && s.compare(0, p.size(), p) == 0 && (s.size() == p.size() || s[p.size()] == ' ');
}
std::string rest(const std::string& s, const std::string& p)
{
  return s.size() > p.size() ? s.substr(p.size() + 1) : std::string();
}
}  // namespace

Command parseCommand(const std::string& text)
{
  const std::string s = normalizeText(text);
  Command c;
  if (s == "pause")
    c.action = Action::PAUSE;
  else if (s == "resume")
    c.action = Action::RESUME;
  else if (s == "where am i")
    c.action = Action::WHERE_AM_I;
  else if (s == "what is ahead")
    c.action = Action::WHAT_IS_AHEAD;
  else if (s == "yes")
    c.action = Action::YES;
  else if (s == "no")
    c.action = Action::NO;
  else if (startsWith(s, "save place"))
  {
    c.action = Action::SAVE_PLACE;
    c.name = rest(s, "save place");
  }
  else if (startsWith(s, "take me back"))
  {
    std::string r = rest(s, "take me back");
    if (!r.empty())
    {
      if (!startsWith(r, "to"))
        return Command();
      r = rest(r, "to");
      if (startsWith(r, "the"))
        r = rest(r, "the");
      if (r.empty())
        return Command();
    }
    c.action = Action::GUIDE_BACK;
    c.name = r;
  }
  return c;
}

Action buttonAction(int button, int press)
{
  if (button == BUTTON_A && press == PRESS_SHORT)
    return Action::SAVE_PLACE;
  if (button == BUTTON_A && press == PRESS_LONG)
    return Action::GUIDE_BACK;
  if (button == BUTTON_B && press == PRESS_SHORT)
    return Action::TOGGLE_PAUSE;
  if (button == BUTTON_B && press == PRESS_LONG)
    return Action::WHERE_AM_I;
  return Action::NONE;
}

std::string numberWords(int n)
{
  static const char* ones[] = {"zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine",
                               "ten", "eleven", "twelve", "thirteen", "fourteen", "fifteen", "sixteen",
                               "seventeen", "eighteen", "nineteen"};
  static const char* tens[] = {"", "", "twenty", "thirty", "forty", "fifty", "sixty", "seventy", "eighty", "ninety"};
  if (n < 0 || n > 99)
    return std::to_string(n);
  if (n < 20)
    return ones[n];
  return std::string(tens[n / 10]) + (n % 10 ? std::string(" ") + ones[n % 10] : "");
}

std::string spokenName(const std::string& name)
{
  std::string out;
  size_t i = 0;
  while (i < name.size())
  {
    if (std::isdigit(static_cast<unsigned char>(name[i])))
    {
      size_t j = i;
      while (j < name.size() && std::isdigit(static_cast<unsigned char>(name[j])))
        ++j;
      if (!out.empty() && out.back() != ' ')
        out += ' ';
      out += numberWords(std::atoi(name.substr(i, j - i).c_str()));
      i = j;
    }
    else
    {
      out += (name[i] == '_' || name[i] == '-') ? ' ' : name[i];
      ++i;
    }
  }
  return out;
}
}  // namespace assistive_voice
