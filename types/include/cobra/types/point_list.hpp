#pragma once
/// @file
/// `cobra::types::PointList` ("Geometry.PointList", pure data): a bounded list of named points,
/// the plan a navigation program (3D Slicer, PLUS) sends as OpenIGTLink POINT messages (entry and
/// target points of a needle path, fiducials). Fixed capacity and no heap, so it crosses real-time
/// ports: at most `kCapacity` points, names and group names of at most `kNameLength` characters
/// (longer ones are cut).
///
/// Text form: `[{name = "entry", group = "plan", position = [0.1, 0, 0.05]}, ...]` (position in m).
/// Lua form: an array of tables `{name = "entry", group = "plan", position = {x, y, z}}` (its Lua
/// value, the "position" a KDL.Vector's Lua form). CSV: one text column (the text form; a list has
/// no fixed number of numeric columns). It is one of cobra's own types: `registerBuiltins()`
/// registers it (core registry, Lua, CSV) with the others at start-up; `registerPointList()` does
/// the same for this type alone (the cobra_bridges package calls it, harmless beside
/// registerBuiltins(): registering is idempotent).
/// DDS (where the dds headers are, in a target that uses cobra::dds): the record
/// `PointListWire` below, ROS 2 type `Geometry/msg/PointList`; a package that sends plans over DDS
/// calls `cobra::dds::registerDdsType<cobra::types::PointList>()` beside registerPointList().

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

#include <kdl/frames.hpp>

#include "cobra/core/bounded_string.hpp"
#include "cobra/core/data_type.hpp"

namespace cobra::types {

/// One named point of a PointList.
struct NamedPoint {
  core::BoundedString<31> name;   ///< the point's name ("entry", "target")
  core::BoundedString<31> group;  ///< the group it belongs to (OpenIGTLink's group name: "Fiducial", a plan's name)
  KDL::Vector position;           ///< m, world frame

  friend bool operator==(const NamedPoint& a, const NamedPoint& b) {
    return a.name == b.name && a.group == b.group && a.position == b.position;
  }
};

/// A bounded list of named points: `points[0, count)` are valid.
struct PointList {
  static constexpr std::size_t kCapacity = 32;    ///< points at most
  static constexpr std::size_t kNameLength = 31;  ///< characters of a name or group name at most

  std::array<NamedPoint, kCapacity> points{};
  std::size_t count = 0;

  /// Appends a point (names cut to kNameLength); false, nothing added, when the list is full.
  bool add(std::string_view name, std::string_view group, const KDL::Vector& position) noexcept {
    if (count >= kCapacity) return false;
    points[count].name.assign(name);
    points[count].group.assign(group);
    points[count].position = position;
    ++count;
    return true;
  }
  /// The first point called `name`, or nullptr.
  const NamedPoint* find(std::string_view name) const noexcept {
    for (std::size_t i = 0; i < count; ++i)
      if (points[i].name.view() == name) return &points[i];
    return nullptr;
  }

  /// Equal when the valid points are equal (the unused slots do not count).
  friend bool operator==(const PointList& a, const PointList& b) {
    if (a.count != b.count) return false;
    for (std::size_t i = 0; i < a.count; ++i)
      if (!(a.points[i] == b.points[i])) return false;
    return true;
  }
};

/// Registers Geometry.PointList with the core registry, Lua and CSV (idempotent; at start-up,
/// not on a real-time thread; registerBuiltins() calls it too). Defined in cobra::types (the
/// codecs live there).
void registerPointList();

}  // namespace cobra::types

template <>
struct cobra::core::DataTypeTraits<cobra::types::PointList> {
  static constexpr std::string_view name = "Geometry.PointList";
  static constexpr DataKind kind = DataKind::Pure;
  static constexpr std::string_view format =
      "a list [{name = \"entry\", group = \"plan\", position = [x, y, z]}, ...] of at most 32 points (m), names "
      "of at most 31 characters";
  static constexpr std::string_view cpp = "cobra::types::PointList";
  static constexpr std::string_view header = "<cobra/types/point_list.hpp>";
  static constexpr std::string_view unit = "m";
  static std::string print(const cobra::types::PointList& value);
  static bool parse(std::string_view text, cobra::types::PointList& out);
};

#if __has_include("cobra/dds/codec.hpp")
#include <vector>

#include "cobra/core/record.hpp"
#include "cobra/dds/codec.hpp"

namespace cobra::types {

/// Geometry.PointList on DDS: `positions` x, y, z per point (m), then `labels`, one line per point,
/// its name and group separated by a tab (a tab or newline inside one is sent as a space). A ROS 2
/// node reads it with the IDL of `cobra::dds::idlOf<PointListWire>()` as Geometry/msg/PointList.idl.
struct PointListWire {
  std::vector<double> positions;
  std::string labels;
};

}  // namespace cobra::types

template <>
struct cobra::core::DataTypeTraits<cobra::types::PointListWire> : cobra::core::RecordTraits<cobra::types::PointListWire> {
  static constexpr std::string_view name = "Geometry.PointList";  // the DDS type name: Geometry::msg::dds_::PointList_
  static constexpr auto fields = std::tuple{
      cobra::core::field("positions", &cobra::types::PointListWire::positions, "m", "x, y, z of each point, world"),
      cobra::core::field("labels", &cobra::types::PointListWire::labels, "", "one line per point: name, a tab, group")};
};

/// The transport's threads convert (and allocate); never a component's update.
template <>
struct cobra::dds::DdsCodec<cobra::types::PointList> {
  using Msg = cobra::types::PointListWire;
  using PubSub = RecordPubSubType<Msg>;
  static void toMsg(const cobra::types::PointList& value, Msg& msg) {
    msg.positions.clear();
    msg.labels.clear();
    const auto put = [&](std::string_view text) {
      for (const char c : text) msg.labels += c == '\n' || c == '\t' ? ' ' : c;
    };
    for (std::size_t k = 0; k < value.count; ++k) {
      const auto& p = value.points[k];
      msg.positions.insert(msg.positions.end(), {p.position.x(), p.position.y(), p.position.z()});
      put(p.name.view());
      msg.labels += '\t';
      put(p.group.view());
      msg.labels += '\n';
    }
  }
  /// Points beyond the capacity, or beyond the labels or positions given, are left out.
  static void fromMsg(const Msg& msg, cobra::types::PointList& value) {
    value = cobra::types::PointList{};
    std::string_view labels = msg.labels;
    for (std::size_t k = 0; 3 * k + 2 < msg.positions.size() && !labels.empty(); ++k) {
      const std::size_t end = labels.find('\n');
      const std::string_view line = labels.substr(0, end);
      labels = end == std::string_view::npos ? std::string_view{} : labels.substr(end + 1);
      const std::size_t tab = line.find('\t');
      const double* v = msg.positions.data() + 3 * k;
      if (!value.add(line.substr(0, tab), tab == std::string_view::npos ? std::string_view{} : line.substr(tab + 1),
                     KDL::Vector(v[0], v[1], v[2])))
        break;
    }
  }
};
#endif
