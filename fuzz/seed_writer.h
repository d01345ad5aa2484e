// seed_writer.h — what the seed makers (make_*_seeds.cpp) share: the output
// folder from the command line, and writing one seed file.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace atmo_fuzz {

// argv[1], the corpus folder to write; exits with a usage line without it.
inline std::string seed_dir(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
    std::exit(2);
  }
  return argv[1];
}

inline void write_seed(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  std::printf("%s: %zu bytes\n", path.c_str(), bytes.size());
}

}  // namespace atmo_fuzz
