#pragma once
/// @file
/// A JSON document read whole (the editor's requests: studio/PROTOCOL.md "The editor"): null,
/// booleans, numbers, strings, arrays and objects (members in the order written). Not for the
/// run's paths: it allocates freely.

#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace cobra::studio::json {

class Value {
 public:
  enum class Kind { Null, Bool, Number, String, Array, Object };

  Value() = default;
  Kind kind() const { return kind_; }
  bool isNull() const { return kind_ == Kind::Null; }
  bool isObject() const { return kind_ == Kind::Object; }
  bool isArray() const { return kind_ == Kind::Array; }
  bool isString() const { return kind_ == Kind::String; }
  bool isNumber() const { return kind_ == Kind::Number; }
  bool isBool() const { return kind_ == Kind::Bool; }

  bool boolean() const { return boolean_; }
  double number() const { return number_; }
  const std::string& string() const { return string_; }
  const std::vector<Value>& items() const { return items_; }
  const std::vector<std::pair<std::string, Value>>& members() const { return members_; }
  /// Member `key` of an object, or nullptr (also when this is not an object).
  const Value* find(std::string_view key) const;

  /// "an object", "the string \"x\"", "the number 3": what this is, for messages.
  std::string describe() const;

  static Value makeBool(bool b);
  static Value makeNumber(double n);
  static Value makeString(std::string s);
  static Value makeArray(std::vector<Value> items);
  static Value makeObject(std::vector<std::pair<std::string, Value>> members);

 private:
  Kind kind_ = Kind::Null;
  bool boolean_ = false;
  double number_ = 0.0;
  std::string string_;
  std::vector<Value> items_;
  std::vector<std::pair<std::string, Value>> members_;
};

/// Parses `text` (one JSON value, nothing after it but blanks).
/// @throws std::runtime_error "JSON: line L, column C: what was expected".
Value parse(std::string_view text);

}  // namespace cobra::studio::json
