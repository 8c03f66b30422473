// Writes the IDL of the dds tests' ProbeReading record (idlOf) to the file named by its argument:
// the build runs fastddsgen on it, and dds_idl_test compares the generated type's bytes with the
// record's own wire.
#include <fstream>
#include <iostream>

#include "cobra/dds/idl.hpp"
#include "test_records.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: dds_record_idl_writer <file.idl>\n";
    return 2;
  }
  std::ofstream out(argv[1]);
  out << cobra::dds::idlOf<cobra::dds::test::ProbeReading>();
  return out ? 0 : 1;
}
