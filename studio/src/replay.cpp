#include "cobra/studio/replay.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "cobra/studio/bridge.hpp"
#include "cobra/studio/json.hpp"

namespace cobra::studio {
namespace {

void writeFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cobra studio: cannot write " + path.string());
}

}  // namespace

std::string writeReplayFolder(const std::filesystem::path& folder, const std::string& recording_json,
                              const std::filesystem::path& web_folder,
                              const std::vector<std::pair<std::string, std::filesystem::path>>& meshes) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw std::runtime_error("cobra studio: cannot create " + folder.string() + ": " + error.message());
  if (!meshes.empty()) std::filesystem::create_directories(folder / "meshes", error);
  for (const auto& [name, file] : meshes) {
    std::filesystem::copy_file(file, folder / "meshes" / (name + file.extension().string()),
                               std::filesystem::copy_options::overwrite_existing, error);
    if (error) throw std::runtime_error("cobra studio: cannot copy the mesh " + file.string() + ": " + error.message());
  }
  writeFile(folder / "recording.json", recording_json);
  // The page reads window.COBRA_RECORDING when it is opened from the file system (no server).
  writeFile(folder / "recording.js", "window.COBRA_RECORDING = " + recording_json + ";\n");
  if (web_folder.empty() || !std::filesystem::is_regular_file(web_folder / "index.html")) return "studio/recording.json";
  std::filesystem::copy(web_folder, folder,
                        std::filesystem::copy_options::recursive | std::filesystem::copy_options::overwrite_existing, error);
  if (error) throw std::runtime_error("cobra studio: cannot copy the web page from " + web_folder.string() + " to " +
                                      folder.string() + ": " + error.message());
  return "studio/index.html";
}

Replay::Replay(const std::filesystem::path& run_folder) : folder_(run_folder / "studio") {
  const std::string name = run_folder.string();
  if (!std::filesystem::is_directory(run_folder)) throw std::runtime_error(name + ": no such folder (give a run folder of cobra run APP --report DIR)");
  const std::filesystem::path file = run_folder / "studio" / "recording.json";
  if (!std::filesystem::is_regular_file(file))
    throw std::runtime_error(name + ": not a run folder with a recording: no studio/recording.json (cobra run APP --report " +
                             name + " writes it for an application with a run.studio table)");
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  const std::string all = text.str();
  const auto malformed = [&](const std::string& why) {
    return std::runtime_error(file.string() + ": not a studio recording: expected {\"model\": {...}, \"frames\": [...], \"events\": [...]}" + why);
  };
  json::Json recording;
  try {
    recording = json::parse(all);
  } catch (const std::runtime_error& e) {
    throw malformed(std::string(" (") + e.what() + ")");
  }
  const json::Json* model = json::find(recording, "model");
  const json::Json* frames = json::find(recording, "frames");
  if (model == nullptr || frames == nullptr || !frames->is_array()) throw malformed("");
  model_ = model->dump();
  json::Json served = {{"frames", std::move(recording["frames"])}};
  const json::Json* events = json::find(recording, "events");
  served["events"] = events != nullptr ? *events : json::Json::array();
  if (const json::Json* end = json::find(recording, "end")) served["end"] = *end;  // how the run ended (older recordings: none)
  frames_ = served.dump();
}

std::string Replay::model(int& status) {
  status = 200;
  return model_;
}

std::string Replay::recording() { return frames_; }

bool Replay::latestFrame(std::uint64_t&, std::string&) { return false; }

void Replay::takeMessages(std::vector<std::string>&) {}

InputAnswer Replay::input(const std::string&) { return {409, "replay: no inputs"}; }

std::filesystem::path Replay::mesh(const std::string& name) {
  if (name.find('/') != std::string::npos) return {};
  for (const char* extension : {".stl", ".STL", ".obj", ".OBJ"})
    if (std::filesystem::is_regular_file(folder_ / "meshes" / (name + extension))) return folder_ / "meshes" / (name + extension);
  return {};
}

}  // namespace cobra::studio
