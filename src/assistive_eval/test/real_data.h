#pragma once
// Where the real camera data of issue 9 lives: $ASSISTIVE_REAL_DATA, else the CMake default (the
// folder beside the workspace, <workspace>/../shared/data/real).
#include <cstdlib>
#include <string>
#include <sys/stat.h>

#ifndef ASSISTIVE_REAL_DATA_DIR
#define ASSISTIVE_REAL_DATA_DIR "../shared/data/real"
#endif

inline std::string realDataDir()
{
  const char* e = std::getenv("ASSISTIVE_REAL_DATA");
  return (e && *e) ? std::string(e) : std::string(ASSISTIVE_REAL_DATA_DIR);
}

inline bool pathExists(const std::string& p)
{
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

/// Skips the calling test with a message when `rel` is missing below the data folder.
#define REQUIRE_REAL_DATA(rel)                                                                     \
  do                                                                                               \
  {                                                                                                \
    if (!pathExists(realDataDir() + "/" + (rel)))                                                  \
      GTEST_SKIP() << "SKIPPED: real data not found at " << realDataDir() << "/" << (rel)          \
                   << " (set ASSISTIVE_REAL_DATA)";                                                \
  } while (0)
