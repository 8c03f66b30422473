// Generates a component into a package folder through the editor's generate route, as the page
// does (Editor::handle("POST", "generate", ...)): tools/cobra/test/new_component_test.sh then
// builds it against an installed cobra and runs its generated test.
// Usage: studio_editor_generate PACKAGE_FOLDER PACKAGE

#include <cstdio>
#include <string>

#include "cobra/studio/editor.hpp"
#include "cobra/studio/json.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s PACKAGE_FOLDER PACKAGE\n", argv[0]);
    return 2;
  }
  cobra::studio::Editor editor;
  const std::string body = "{\"folder\":" + cobra::studio::json::quoted(argv[1]) +
                           ",\"component\":{\"name\":\"EditorMade\",\"role\":\"decision\",\"package\":" +
                           cobra::studio::json::quoted(argv[2]) +
                           ",\"doc\":\"the \\\"level\\\" of a force (N)\",\"inputs\":[{\"name\":\"force\",\"type\":\"Wrench\",\"unit\":\"N\"}],"
                           "\"event_inputs\":[{\"name\":\"tick\",\"type\":\"Event\"}],"
                           "\"outputs\":[{\"name\":\"level\",\"type\":\"double\",\"unit\":\"N\"}],"
                           "\"properties\":[{\"name\":\"threshold\",\"type\":\"double\",\"unit\":\"N\"}]}}";
  const cobra::studio::EditorAnswer answer = editor.handle("POST", "generate", body);
  std::printf("%d %s\n", answer.status, answer.body.c_str());
  return answer.status == 200 ? 0 : 1;
}
