#include "edit_command.hpp"

#include <chrono>
#include <cstdio>
#include <thread>

#include "cobra/studio/editor.hpp"
#include "cobra/studio/server.hpp"

namespace cobra::tools {

int editDeployment(const std::string& path, const StudioCommandOptions& options, const std::atomic<bool>& interrupted) {
  studio::Editor editor;
  if (!path.empty()) {
    const std::string error = editor.open(path);
    if (!error.empty()) std::fprintf(stderr, "cobra: %s\n", error.c_str());
  }
  studio::NoRunSource no_run;
  studio::ServerOptions server_options;
  server_options.bind = options.bind;
  server_options.port = options.port;
  server_options.tls_cert = options.tls_cert;
  server_options.tls_key = options.tls_key;
  server_options.web_folder = studio::findWebFolder(options.executable);
  server_options.editor = &editor;
  studio::Server server(no_run, server_options);
  if (!studio::isLoopback(options.bind))
    std::printf("editor: warning: listening on %s (TLS): whoever reaches it with the token can read and write files\n",
                options.bind.c_str());
  if (server_options.web_folder.empty())
    std::printf("editor: warning: no web front end found (studio/web/dist, or set COBRA_STUDIO_WEB); /api/editor works\n");
  std::printf("editor: %s\n", studio::editorUrl(server).c_str());
  std::fflush(stdout);
  while (!interrupted.load()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  return 0;
}

}  // namespace cobra::tools
