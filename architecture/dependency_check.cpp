#include "dependency_check.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <queue>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

namespace cobra::architecture {
namespace {

namespace fs = std::filesystem;

// The first folder of `list` that `path` ("components/signal/src/x.cpp") is in, or "".
std::string folderOf(const std::string& path, const std::vector<std::string>& list) {
  for (const std::string& folder : list)
    if (path == folder || path.rfind(folder + "/", 0) == 0) return folder;
  return {};
}

bool isLibrary(const Target& t) { return t.type.find("LIBRARY") != std::string::npos; }

bool isSource(const fs::path& file) {
  static const std::set<std::string> kExtensions = {".hpp", ".h", ".hh", ".cpp", ".cc", ".cxx", ".inl", ".ipp"};
  return kExtensions.count(file.extension().string()) != 0;
}

// Folders never looked into: builds, the web front end's packages, version control.
bool ignoredFolder(const fs::path& folder) {
  const std::string name = folder.filename().string();
  return name == ".git" || name == "node_modules" || name.rfind("build", 0) == 0;
}

// Every source file under `folder`, relative to `root`, except in folders named in `skipped`.
void collect(const fs::path& root, const fs::path& folder, const std::vector<std::string>& skipped, std::vector<std::string>& out) {
  std::error_code error;
  for (fs::recursive_directory_iterator it(folder, error), end; it != end; it.increment(error)) {
    if (error) break;
    if (it->is_directory()) {
      const std::string name = it->path().filename().string();
      if (ignoredFolder(it->path()) || std::find(skipped.begin(), skipped.end(), name) != skipped.end()) it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file() && isSource(it->path())) out.push_back(it->path().lexically_relative(root).generic_string());
  }
  std::sort(out.begin(), out.end());
}

}  // namespace

std::vector<Target> readTargets(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read the target list (written when CMake configures)");
  std::vector<Target> targets;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<std::string> fields;
    std::stringstream columns(line);
    for (std::string field; std::getline(columns, field, '\t');) fields.push_back(field);
    if (fields.size() < 3) throw std::runtime_error(file.string() + ": expected name, type, folder and links, got \"" + line + "\"");
    Target t{fields[0], fields[1], fields[2], {}};
    if (fields.size() > 3) {
      std::stringstream links(fields[3]);
      for (std::string link; links >> link;) t.links.push_back(link);
    }
    targets.push_back(std::move(t));
  }
  return targets;
}

std::vector<Violation> linkViolations(const std::vector<Target>& targets, const Rule& rule) {
  std::map<std::string, const Target*> by_name;
  for (const Target& t : targets) by_name[t.name] = &t;
  std::vector<Violation> out;
  for (const Target& start : targets) {
    const std::string module = folderOf(start.folder, rule.checked);
    if (module.empty() || !(rule.executables || isLibrary(start))) continue;
    // Breadth first from `start`, through targets neither checked nor forbidden.
    std::map<std::string, std::string> parent{{start.name, ""}};
    std::queue<const Target*> next;
    next.push(&start);
    while (!next.empty()) {
      const Target* t = next.front();
      next.pop();
      for (const std::string& link : t->links) {
        if (parent.count(link) != 0) continue;
        parent[link] = t->name;
        const auto found = by_name.find(link);
        if (found == by_name.end()) continue;
        const Target& d = *found->second;
        if (const std::string bad = folderOf(d.folder, rule.forbidden); !bad.empty()) {
          std::string chain = d.name;
          for (std::string p = t->name; !p.empty(); p = parent[p]) chain = p + " -> " + chain;
          out.push_back({"target " + start.name + " (" + start.folder + "/) links " + d.name + " (" + d.folder + "/): " + chain +
                             "; " + module + " must not depend on " + bad + "/",
                         start.name + " -> " + d.name});
        } else if (folderOf(d.folder, rule.checked).empty()) {
          next.push(&d);
        }
      }
    }
  }
  return out;
}

std::vector<Violation> includeViolations(const fs::path& root, const Rule& rule) {
  // Every header of the tree, by each of its path's suffixes ("cobra/report/report.hpp", "report/report.hpp", ...).
  std::vector<std::string> headers;
  for (fs::directory_iterator it(root), end; it != end; ++it)
    if (it->is_directory() && !ignoredFolder(it->path())) collect(root, it->path(), {}, headers);
  std::map<std::string, std::vector<std::string>> by_suffix;
  for (const std::string& h : headers) {
    const std::string extension = fs::path(h).extension().string();
    if (extension != ".hpp" && extension != ".h" && extension != ".hh" && extension != ".inl" && extension != ".ipp") continue;
    for (std::string rest = h;;) {
      by_suffix[rest].push_back(h);
      const std::size_t slash = rest.find('/');
      if (slash == std::string::npos) break;
      rest = rest.substr(slash + 1);
    }
  }
  static const std::regex kInclude(R"(^\s*#\s*include\s*([<"])([^>"]+)[>"])");
  std::vector<Violation> out;
  for (const std::string& module : rule.checked) {
    std::vector<std::string> sources;
    if (fs::is_directory(root / module)) collect(root, root / module, rule.skipped, sources);
    for (const std::string& source : sources) {
      std::ifstream in(root / source);
      std::string line;
      for (int number = 1; std::getline(in, line); ++number) {
        std::smatch m;
        if (!std::regex_search(line, m, kInclude)) continue;
        const std::string name = m[2];
        std::string resolved;  // the forbidden header it names, if any
        const fs::path beside = (fs::path(source).parent_path() / name).lexically_normal();
        if (m[1] == "\"" && fs::is_regular_file(root / beside)) {
          if (!folderOf(beside.generic_string(), rule.forbidden).empty()) resolved = beside.generic_string();
        } else if (const auto found = by_suffix.find(name); found != by_suffix.end()) {
          const bool all_forbidden = std::all_of(found->second.begin(), found->second.end(), [&](const std::string& h) {
            return !folderOf(h, rule.forbidden).empty();
          });
          if (all_forbidden) resolved = found->second.front();
        }
        if (resolved.empty()) continue;
        out.push_back({source + ":" + std::to_string(number) + ": #include " + std::string(m[1]) + name +
                           (m[1] == "<" ? ">" : "\"") + " is " + resolved + "; " + folderOf(source, rule.checked) +
                           " must not depend on " + folderOf(resolved, rule.forbidden) + "/",
                       source + " -> " + resolved});
      }
    }
  }
  return out;
}

std::vector<Violation> notAllowed(const std::vector<Violation>& violations, const std::vector<std::string>& allowed,
                                  std::vector<std::string>& unused) {
  std::vector<Violation> out;
  std::set<std::string> used;
  for (const Violation& v : violations) {
    if (std::find(allowed.begin(), allowed.end(), v.key) != allowed.end()) {
      used.insert(v.key);
    } else {
      out.push_back(v);
    }
  }
  unused.clear();
  for (const std::string& a : allowed)
    if (used.count(a) == 0) unused.push_back(a);
  return out;
}

}  // namespace cobra::architecture
