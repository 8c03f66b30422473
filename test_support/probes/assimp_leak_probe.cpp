// The leak that test_support/lsan.supp suppresses (assimp 5.2's ASCII STL reader on a malformed
// file), shown through cobra's own path to it: planning::loadMesh refuses the file, and assimp
// keeps the mesh and node it allocated. ctest runs it under ASan without the suppressions,
// expecting LeakSanitizer's report inside libassimp (the suppression must not outlive the
// defect silently), and with them, expecting a clean exit (test_support/CMakeLists.txt).
#include <cstdio>
#include <exception>

#include "cobra/planning/geometry.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: assimp_leak_probe <malformed mesh file>\n");
    return 2;
  }
  try {
    cobra::planning::loadMesh(argv[1], 1.0);
  } catch (const std::exception& e) {
    std::printf("assimp_leak_probe: refused: %s\n", e.what());
    return 0;
  }
  std::fprintf(stderr, "assimp_leak_probe: %s was read; expected a malformed file\n", argv[1]);
  return 1;
}
