// generate_world: write a random world YAML (layout, furniture, materials, a clear walk) for a seed.
//   rosrun assistive_sim generate_world --seed N [--kind office|lobby|corridor|hall|street|home|shop] --out W.yaml
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include <assistive_sim/world_generator.h>

using namespace assistive_sim;

namespace
{
void usage(std::ostream& os = std::cerr)
{
  os << "usage: generate_world --seed N [--kind office|lobby|corridor|hall|street|home|shop] [--people N] [--pale] --out W.yaml\n"
        "  writes a world file (README \"World files\") with a random layout of that kind (default: chosen\n"
        "  by the seed among the first five), furniture, materials and a collision-free walk; the same seed\n"
        "  gives the same file. Doorways the walk uses are 0.80-0.90 m clear, halls and aisles 1.2-1.5 m.\n"
        "  --people N (0 .. 100, default 0): N people whose walks cross the generated walk in time\n"
        "  --pale: the kind's texture richness cut to a fifth (below 0.2: bare paint; issue 35), another layout\n";
}

std::string jsonEscape(const std::string& s)
{
  std::string o;
  for (char c : s)
  {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o;
}
}  // namespace

int main(int argc, char** argv)
{
  std::string kind, out;
  long seed = -1;
  int people = 0;
  bool pale = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto val = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        std::cerr << "generate_world: " << a << " needs a value\n";
        usage();
        std::exit(2);
      }
      return argv[++i];
    };
    try
    {
      if (a == "--seed") seed = std::stol(val());
      else if (a == "--kind") kind = val();
      else if (a == "--out") out = val();
      else if (a == "--pale") pale = true;
      else if (a == "--people")
      {
        people = std::stoi(val());
        if (people < 0 || people > 100) throw std::invalid_argument(a);
      }
      else if (a == "-h" || a == "--help")
      {
        usage(std::cout);
        return 0;
      }
      else
      {
        std::cerr << "generate_world: unknown argument " << a << "\n";
        usage();
        return 2;
      }
    }
    catch (const std::exception&)
    {
      std::cerr << "generate_world: bad value for " << a << "\n";
      usage();
      return 2;
    }
  }
  if (seed < 0 || seed > 0xffffffffL || out.empty())
  {
    std::cerr << "generate_world: --seed (0 .. 4294967295) and --out are required\n";
    usage();
    return 2;
  }
  GeneratedWorld g;
  try
  {
    WorldGenerator gen(static_cast<uint32_t>(seed), kind, people);
    gen.setPale(pale);
    g = gen.generate();
  }
  catch (const std::invalid_argument& e)
  {
    std::cerr << "generate_world: " << e.what() << "\n";
    usage();
    return 2;
  }
  catch (const std::exception& e)
  {
    std::cerr << e.what() << "\n";
    return 1;
  }
  std::ofstream f(out, std::ios::binary);
  f << g.yaml;
  f.close();
  if (!f)
  {
    std::cerr << "generate_world: cannot write " << out << "\n";
    return 1;
  }
  std::printf("world %s: %d elements, %zu solids, %zu waypoints, walk %.1f m, %d people\n", g.world.name.c_str(),
              g.elements, g.world.solids.size(), g.world.trajectory.waypoints.size(), g.walk_length, g.people);
  std::printf("{\"seed\": %ld, \"kind\": \"%s\", \"elements\": %d, \"walk_length_m\": %.2f, \"people\": %d, \"out\": \"%s\"}\n",
              seed, g.kind.c_str(), g.elements, g.walk_length, g.people, jsonEscape(out).c_str());
  return 0;
}
