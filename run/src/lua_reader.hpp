#pragma once
// Reading the `run` table from Lua (private to cobra::run): a Reader is one table on the Lua
// stack with its path ("run.tracking[2]") and the line it is written at, for messages
// "file:line: run.tracking[2]: what was expected". Section (cobra/run/section.hpp) is the face
// of it an observer of a package sees.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <lua.hpp>

#include "cobra/run/run_spec.hpp"

namespace cobra::run::detail {

// The lines of `file` (to find where an entry is written: Lua keeps no line per table entry).
inline std::vector<std::string> linesOf(const std::string& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Reads one Lua table (at the top of the stack while it lives) with its path for messages.
class Reader {
 public:
  Reader(lua_State* L, const std::string& file, std::vector<std::string> lines, std::string path, int line)
      : L_(L), file_(file), lines_(std::move(lines)), path_(std::move(path)), line_(line) {}

  Where where() const { return {file_, line_}; }
  const std::string& path() const { return path_; }

  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(where().text() + ": " + path_ + ": " + what);
  }

  // The first line at or after this entry's that contains `text` (quoted), for its children.
  int lineOf(const std::string& text) const {
    for (std::size_t i = static_cast<std::size_t>(std::max(line_ - 1, 0)); i < lines_.size(); ++i)
      if (lines_[i].find("\"" + text + "\"") != std::string::npos || lines_[i].find("'" + text + "'") != std::string::npos)
        return static_cast<int>(i + 1);
    return line_;
  }

  bool has(const char* key) const {
    lua_getfield(L_, -1, key);
    const bool present = !lua_isnil(L_, -1);
    lua_pop(L_, 1);
    return present;
  }

  std::string string(const char* key, bool required, const std::string& fallback = {}) const {
    lua_getfield(L_, -1, key);
    if (lua_isnil(L_, -1)) {
      lua_pop(L_, 1);
      if (required) fail("needs `" + std::string(key) + "` (a string)");
      return fallback;
    }
    if (lua_type(L_, -1) != LUA_TSTRING) {
      lua_pop(L_, 1);
      fail("`" + std::string(key) + "` must be a string");
    }
    std::string value = lua_tostring(L_, -1);
    lua_pop(L_, 1);
    return value;
  }

  double number(const char* key, double fallback, bool positive = false) const {
    lua_getfield(L_, -1, key);
    if (lua_isnil(L_, -1)) {
      lua_pop(L_, 1);
      return fallback;
    }
    if (!lua_isnumber(L_, -1)) {
      lua_pop(L_, 1);
      fail("`" + std::string(key) + "` must be a number");
    }
    const double value = lua_tonumber(L_, -1);
    lua_pop(L_, 1);
    if (!std::isfinite(value) || (positive && value <= 0.0)) fail("`" + std::string(key) + "` must be a finite" +
                                                                   (positive ? " positive" : "") + " number");
    return value;
  }

  bool boolean(const char* key, bool fallback) const {
    lua_getfield(L_, -1, key);
    const bool value = lua_isnil(L_, -1) ? fallback : lua_toboolean(L_, -1) != 0;
    lua_pop(L_, 1);
    return value;
  }

  // A list of strings (or a single string) under `key`.
  std::vector<std::string> strings(const char* key) const {
    std::vector<std::string> out;
    lua_getfield(L_, -1, key);
    if (lua_type(L_, -1) == LUA_TSTRING) {
      out.push_back(lua_tostring(L_, -1));
    } else if (lua_istable(L_, -1)) {
      const lua_Integer n = luaL_len(L_, -1);
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_rawgeti(L_, -1, i);
        if (lua_type(L_, -1) != LUA_TSTRING) {
          lua_pop(L_, 2);
          fail("`" + std::string(key) + "` must be a list of strings (entry " + std::to_string(i) + " is not)");
        }
        out.push_back(lua_tostring(L_, -1));
        lua_pop(L_, 1);
      }
    } else if (!lua_isnil(L_, -1)) {
      lua_pop(L_, 1);
      fail("`" + std::string(key) + "` must be a string or a list of strings");
    }
    lua_pop(L_, 1);
    return out;
  }

  // A list of positive numbers under `key`.
  std::vector<double> numbers(const char* key) const {
    std::vector<double> out;
    lua_getfield(L_, -1, key);
    const lua_Integer n = luaL_len(L_, -1);
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L_, -1, i);
      const bool number = lua_isnumber(L_, -1) != 0;
      const double value = number ? lua_tonumber(L_, -1) : 0.0;
      lua_pop(L_, 1);
      if (!number || !(value > 0.0) || !std::isfinite(value)) {
        lua_pop(L_, 1);
        fail("`" + std::string(key) + "` must be a list of positive numbers (entry " + std::to_string(i) + " is not)");
      }
      out.push_back(value);
    }
    lua_pop(L_, 1);
    return out;
  }

  // Calls `each` with a Reader on every entry of the list under `key` (tables), their line
  // found from the string `identify` returns for the entry.
  template <class F>
  void list(const char* key, F&& each, const char* identify = "name") const {
    lua_getfield(L_, -1, key);
    if (lua_isnil(L_, -1)) {
      lua_pop(L_, 1);
      return;
    }
    if (!lua_istable(L_, -1)) {
      lua_pop(L_, 1);
      fail("`" + std::string(key) + "` must be a list of tables");
    }
    Reader(L_, file_, lines_, path_ + "." + key, line_).items(each, identify);
    lua_pop(L_, 1);
  }

  // Calls `each` with a Reader on every entry of this list (its table on top of the stack), as
  // `list` does for a list under a key.
  template <class F>
  void items(F&& each, const char* identify = "name") const {
    if (!lua_istable(L_, -1)) fail("must be a list of tables");
    const lua_Integer n = luaL_len(L_, -1);
    int line = line_;
    for (lua_Integer i = 1; i <= n; ++i) {
      lua_rawgeti(L_, -1, i);
      Reader entry(L_, file_, lines_, path_ + "[" + std::to_string(i) + "]", line);
      if (!lua_istable(L_, -1)) entry.fail("must be a table");
      const std::string id = identify ? entry.string(identify, false) : std::string();
      if (!id.empty()) entry.line_ = line = lineOf(id);
      each(entry);
      lua_pop(L_, 1);
    }
  }

  // The keys of this table (its string keys; `bad` is called with a key that is not a string).
  std::vector<std::string> keys() const {
    std::vector<std::string> out;
    lua_pushnil(L_);
    while (lua_next(L_, -2) != 0) {
      lua_pop(L_, 1);
      if (lua_type(L_, -1) == LUA_TSTRING) out.emplace_back(lua_tostring(L_, -1));
    }
    return out;
  }

  const std::string& file() const { return file_; }
  const std::vector<std::string>& lines() const { return lines_; }

  // Calls `f` with a Reader on the table under `key` when there is one.
  template <class F>
  bool table(const char* key, F&& f) const {
    lua_getfield(L_, -1, key);
    if (lua_isnil(L_, -1)) {
      lua_pop(L_, 1);
      return false;
    }
    if (!lua_istable(L_, -1)) {
      lua_pop(L_, 1);
      fail("`" + std::string(key) + "` must be a table");
    }
    Reader sub(L_, file_, lines_, path_ + "." + key, line_);
    f(sub);
    lua_pop(L_, 1);
    return true;
  }

  // Calls `each(name, entry)` on every `name = value` of the table under `key`, in the order of
  // their lines (Lua keeps none), each entry's line the first at or after this one writing `name =`.
  template <class F>
  void entries(const char* key, F&& each) const {
    std::vector<std::pair<int, std::string>> names;
    table(key, [&](const Reader& t) {
      lua_pushnil(L_);
      while (lua_next(L_, -2) != 0) {
        lua_pop(L_, 1);
        if (lua_type(L_, -1) != LUA_TSTRING) {
          lua_pop(L_, 1);
          t.fail("entries must be written name = ...");
        }
        const std::string name = lua_tostring(L_, -1);
        names.emplace_back(t.lineOfKey(name), name);
      }
      std::sort(names.begin(), names.end());
      for (const auto& [line, name] : names) {
        lua_getfield(L_, -1, name.c_str());
        Reader entry(L_, file_, lines_, t.path_ + "." + name, line);
        each(name, entry);
        lua_pop(L_, 1);
      }
    });
  }

  // The first line at or after this entry's that writes `name =` (a key of a table).
  int lineOfKey(const std::string& name) const {
    for (std::size_t i = static_cast<std::size_t>(std::max(line_ - 1, 0)); i < lines_.size(); ++i) {
      for (std::size_t at = lines_[i].find(name); at != std::string::npos; at = lines_[i].find(name, at + 1)) {
        const bool starts = at == 0 || !(std::isalnum(static_cast<unsigned char>(lines_[i][at - 1])) || lines_[i][at - 1] == '_');
        std::size_t after = at + name.size();
        while (after < lines_[i].size() && lines_[i][after] == ' ') ++after;
        if (starts && after < lines_[i].size() && lines_[i][after] == '=') return static_cast<int>(i + 1);
      }
    }
    return line_;
  }

  lua_State* state() const { return L_; }
  int line() const { return line_; }
  void setLine(int line) { line_ = line; }

 private:
  lua_State* L_;
  std::string file_;
  std::vector<std::string> lines_;
  std::string path_;
  int line_;
};

// "Comp.member" -> (Comp, member).
inline std::pair<std::string, std::string> split(const Reader& r, const std::string& path, const char* member) {
  const auto dot = path.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == path.size())
    r.fail("'" + path + "' must be written Component." + member);
  return {path.substr(0, dot), path.substr(dot + 1)};
}

// "chart:state path" -> (chart, state).
inline std::pair<std::string, std::string> chartState(const Reader& r, const std::string& text) {
  const auto colon = text.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size())
    r.fail("state '" + text + "' must be written chart:state path, e.g. needle:root.WaitCryoCycle");
  return {text.substr(0, colon), text.substr(colon + 1)};
}

}  // namespace cobra::run::detail
