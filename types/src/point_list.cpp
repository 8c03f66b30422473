// Geometry.PointList: its text form, Lua codec and CSV codec, and its registration.
#include "cobra/types/point_list.hpp"

#include <lua.hpp>

#include "cobra/components/reporting/csv_codec.hpp"
#include "cobra/core/record.hpp"
#include "cobra/script/lua_codec.hpp"
#include "cobra/types/register_type.hpp"

using cobra::types::NamedPoint;
using cobra::types::PointList;

namespace cobra::script {

/// An array of tables {name = "entry", group = "plan", position = {x, y, z}} (m).
template <>
struct LuaCodec<PointList> {
  static std::string_view form();
  static void read(lua_State* L, int index, PointList& out);
  static void push(lua_State* L, const PointList& value);
};

}  // namespace cobra::script

namespace cobra::components {

/// A list has no fixed number of values: one text column (its text form).
template <>
struct CsvCodec<PointList> : TextCsvCodec<PointList> {};

}  // namespace cobra::components

namespace cobra::script {

namespace {
constexpr std::string_view kListForm =
    "an array of at most 32 points {name = \"entry\", group = \"plan\", position = {x, y, z}} (m)";

// t[key] of the table at `point` as a string of at most PointList::kNameLength characters.
std::string_view readName(lua_State* L, int table, int point, std::string_view key, std::size_t k) {
  lua_codec::pushRawField(L, point, key);
  if (lua_type(L, -1) != LUA_TSTRING)
    lua_codec::refuse(L, table, kListForm, "point " + std::to_string(k + 1) + ": " + std::string(key) + " is not a string");
  std::size_t length = 0;
  const char* text = lua_tolstring(L, -1, &length);
  if (length > PointList::kNameLength)
    lua_codec::refuse(L, table, kListForm,
                      "point " + std::to_string(k + 1) + ": " + std::string(key) + " is longer than 31 characters");
  return {text, length};  // valid while the string stays on the stack (the guard pops it)
}
}  // namespace

std::string_view LuaCodec<PointList>::form() { return kListForm; }

void LuaCodec<PointList>::read(lua_State* L, int index, PointList& out) {
  index = lua_absindex(L, index);
  if (lua_type(L, index) != LUA_TTABLE) lua_codec::refuse(L, index, kListForm);
  lua_codec::StackGuard guard(L);
  const auto count = static_cast<std::size_t>(lua_rawlen(L, index));
  if (count > PointList::kCapacity) lua_codec::refuse(L, index, kListForm, std::to_string(count) + " points");
  PointList list;
  for (std::size_t k = 0; k < count; ++k) {
    if (lua_rawgeti(L, index, static_cast<lua_Integer>(k + 1)) != LUA_TTABLE)
      lua_codec::refuse(L, index, kListForm, "point " + std::to_string(k + 1) + " is not a table");
    const int point = lua_gettop(L);
    static constexpr std::string_view kKeys[] = {"name", "group", "position"};
    if (const std::string unknown = lua_codec::unknownKey(L, point, kKeys); !unknown.empty())
      lua_codec::refuse(L, index, kListForm, "point " + std::to_string(k + 1) + " has the key " + unknown);
    const std::string_view name = readName(L, index, point, "name", k);
    const std::string_view group = readName(L, index, point, "group", k);
    lua_codec::pushRawField(L, point, "position");
    KDL::Vector position;
    LuaCodec<KDL::Vector>::read(L, -1, position);
    list.add(name, group, position);
    lua_settop(L, point - 1);
  }
  out = list;
}

void LuaCodec<PointList>::push(lua_State* L, const PointList& value) {
  lua_createtable(L, static_cast<int>(value.count), 0);
  for (std::size_t k = 0; k < value.count; ++k) {
    const NamedPoint& p = value.points[k];
    lua_codec::newTable(L, 3);
    lua_pushlstring(L, p.name.view().data(), p.name.size());
    lua_codec::setField(L, "name");
    lua_pushlstring(L, p.group.view().data(), p.group.size());
    lua_codec::setField(L, "group");
    LuaCodec<KDL::Vector>::push(L, p.position);
    lua_codec::setField(L, "position");
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
}

}  // namespace cobra::script

namespace cobra::core {

std::string DataTypeTraits<PointList>::print(const PointList& value) {
  std::string text = "[";
  for (std::size_t k = 0; k < value.count; ++k) {
    const NamedPoint& p = value.points[k];
    if (k > 0) text += ", ";
    text += "{name = " + record_detail::quote(p.name.view()) + ", group = " + record_detail::quote(p.group.view()) +
            ", position = " + DataTypeTraits<KDL::Vector>::print(p.position) + "}";
  }
  return text + "]";
}

bool DataTypeTraits<PointList>::parse(std::string_view text, PointList& out) {
  const auto trim = [](std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\n')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\n')) s.remove_suffix(1);
    return s;
  };
  text = trim(text);
  if (text.size() < 2 || text.front() != '[' || text.back() != ']') return false;
  text = trim(text.substr(1, text.size() - 2));
  PointList list;
  // Each item is one {...} (strings may hold braces and commas: skip quoted text).
  while (!text.empty()) {
    if (text.front() != '{') return false;
    std::size_t end = 0;
    int depth = 0;
    bool quoted = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
      const char c = text[i];
      if (quoted) {
        if (c == '\\') ++i;
        else if (c == '"') quoted = false;
      } else if (c == '"') {
        quoted = true;
      } else if (c == '{' || c == '[') {
        ++depth;
      } else if ((c == '}' || c == ']') && --depth == 0) {
        end = i + 1;
        break;
      }
    }
    if (end == 0) return false;
    std::vector<std::pair<std::string_view, std::string_view>> items;
    if (!record_detail::split(text.substr(0, end), items) || items.size() != 3) return false;
    std::string name, group;
    KDL::Vector position;
    int seen = 0;
    for (const auto& [key, item] : items) {
      if (key == "name" && record_detail::unquote(item, name) && name.size() <= PointList::kNameLength) seen |= 1;
      else if (key == "group" && record_detail::unquote(item, group) && group.size() <= PointList::kNameLength) seen |= 2;
      else if (key == "position" && DataTypeTraits<KDL::Vector>::parse(item, position)) seen |= 4;
      else return false;
    }
    if (seen != 7 || !list.add(name, group, position)) return false;
    text = trim(text.substr(end));
    if (!text.empty()) {
      if (text.front() != ',') return false;
      text = trim(text.substr(1));
      if (text.empty()) return false;
    }
  }
  out = list;
  return true;
}

}  // namespace cobra::core

namespace cobra::types {

void registerPointList() { registerType<PointList>(); }

}  // namespace cobra::types
