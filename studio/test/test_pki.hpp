#pragma once
// A test certificate authority and a TLS server certificate for the studio server's tests:
// ca.{crt,key} and server.{crt,key} (CN=localhost, subjectAltName DNS:localhost, IP:127.0.0.1,
// signed by the CA) in a scratch folder. tools/make_test_pki.sh makes them when the repository has
// it; else the same two with the openssl command line here. The folder goes when the process ends.

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "cobra/test_support/test_support.hpp"

namespace cobra::studio::test_pki {

inline std::filesystem::path makeTestPki() {
  const std::filesystem::path dir = ::cobra::test_support::scratchPath("studio_pki");
  if (std::filesystem::is_regular_file(dir / "server.key")) return dir;
  std::filesystem::create_directories(dir);
  // Removed when the test process ends (the folder is this process's: scratchPath has its pid).
  static const struct Remove {
    std::filesystem::path dir;
    ~Remove() {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  } remove{dir};
  const std::string d = "'" + dir.string() + "'";
  const std::filesystem::path script = std::filesystem::path(COBRA_SOURCE_DIR) / "tools" / "make_test_pki.sh";
  std::string command;
  if (std::filesystem::is_regular_file(script)) {
    command = "bash '" + script.string() + "' " + d + " >/dev/null";
  } else {
    const std::string key = " -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes";
    command = "cd " + d + " && openssl req -x509" + key + " -days 2 -subj '/CN=cobra studio test CA' -keyout ca.key -out ca.crt" +
              " 2>/dev/null && openssl req" + key + " -subj /CN=localhost -keyout server.key -out server.csr 2>/dev/null" +
              " && printf 'subjectAltName=DNS:localhost,IP:127.0.0.1\\nextendedKeyUsage=serverAuth\\n' >server.ext" +
              " && openssl x509 -req -in server.csr -CA ca.crt -CAkey ca.key -CAcreateserial -days 2 -extfile server.ext" +
              " -out server.crt 2>/dev/null";
  }
  if (std::system(command.c_str()) != 0 || !std::filesystem::is_regular_file(dir / "server.key"))
    throw std::runtime_error("test: cannot make the test PKI in " + dir.string() + " (" + command + ")");
  return dir;
}

}  // namespace cobra::studio::test_pki
