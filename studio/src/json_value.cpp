#include "cobra/studio/json_value.hpp"

#include <charconv>
#include <stdexcept>

#include "cobra/studio/json.hpp"

namespace cobra::studio::json {
namespace {

class Parser {
 public:
  explicit Parser(std::string_view text) : text_(text) {}

  Value document() {
    Value v = value(0);
    blanks();
    if (i_ != text_.size()) fail("the end of the document after the value");
    return v;
  }

 private:
  static constexpr int kMaxDepth = 64;  // a request nests a few levels; deeper is an attack

  [[noreturn]] void fail(const std::string& expected) const {
    int line = 1, column = 1;
    for (std::size_t k = 0; k < i_ && k < text_.size(); ++k) {
      if (text_[k] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    throw std::runtime_error("JSON: line " + std::to_string(line) + ", column " + std::to_string(column) + ": expected " +
                             expected);
  }

  void blanks() {
    while (i_ < text_.size() && (text_[i_] == ' ' || text_[i_] == '\n' || text_[i_] == '\r' || text_[i_] == '\t')) ++i_;
  }

  bool literal(std::string_view word) {
    if (text_.substr(i_, word.size()) != word) return false;
    i_ += word.size();
    return true;
  }

  Value value(int depth) {
    if (depth > kMaxDepth) fail("at most " + std::to_string(kMaxDepth) + " nested arrays and objects");
    blanks();
    if (i_ >= text_.size()) fail("a value");
    const char c = text_[i_];
    if (c == '{') return object(depth);
    if (c == '[') return array(depth);
    if (c == '"') return Value::makeString(string());
    if (literal("true")) return Value::makeBool(true);
    if (literal("false")) return Value::makeBool(false);
    if (literal("null")) return Value();
    return Value::makeNumber(number());
  }

  Value object(int depth) {
    ++i_;
    std::vector<std::pair<std::string, Value>> members;
    blanks();
    if (i_ < text_.size() && text_[i_] == '}') {
      ++i_;
      return Value::makeObject(std::move(members));
    }
    while (true) {
      blanks();
      if (i_ >= text_.size() || text_[i_] != '"') fail("a member name (a string)");
      std::string key = string();
      blanks();
      if (i_ >= text_.size() || text_[i_] != ':') fail("':' after the member name");
      ++i_;
      members.emplace_back(std::move(key), value(depth + 1));
      blanks();
      if (i_ < text_.size() && text_[i_] == ',') {
        ++i_;
        continue;
      }
      if (i_ < text_.size() && text_[i_] == '}') {
        ++i_;
        return Value::makeObject(std::move(members));
      }
      fail("',' or '}' in an object");
    }
  }

  Value array(int depth) {
    ++i_;
    std::vector<Value> items;
    blanks();
    if (i_ < text_.size() && text_[i_] == ']') {
      ++i_;
      return Value::makeArray(std::move(items));
    }
    while (true) {
      items.push_back(value(depth + 1));
      blanks();
      if (i_ < text_.size() && text_[i_] == ',') {
        ++i_;
        continue;
      }
      if (i_ < text_.size() && text_[i_] == ']') {
        ++i_;
        return Value::makeArray(std::move(items));
      }
      fail("',' or ']' in an array");
    }
  }

  static void appendUtf8(std::string& out, unsigned code) {
    if (code < 0x80) {
      out += static_cast<char>(code);
    } else if (code < 0x800) {
      out += static_cast<char>(0xC0 | (code >> 6));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else if (code < 0x10000) {
      out += static_cast<char>(0xE0 | (code >> 12));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (code >> 18));
      out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    }
  }

  unsigned hex4() {
    if (i_ + 4 > text_.size()) fail("4 hexadecimal digits after \\u");
    unsigned code = 0;
    const auto [end, ec] = std::from_chars(text_.data() + i_, text_.data() + i_ + 4, code, 16);
    if (ec != std::errc() || end != text_.data() + i_ + 4) fail("4 hexadecimal digits after \\u");
    i_ += 4;
    return code;
  }

  std::string string() {
    ++i_;  // the opening quote
    std::string out;
    while (true) {
      if (i_ >= text_.size()) fail("the closing '\"' of a string");
      const char c = text_[i_++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) fail("no control character inside a string (escape it)");
      if (c != '\\') {
        out += c;
        continue;
      }
      if (i_ >= text_.size()) fail("an escape after '\\'");
      const char e = text_[i_++];
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          unsigned code = hex4();
          if (code >= 0xD800 && code < 0xDC00 && text_.substr(i_, 2) == "\\u") {
            i_ += 2;
            const unsigned low = hex4();
            if (low < 0xDC00 || low > 0xDFFF) fail("a low surrogate after a high one");
            code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
          }
          appendUtf8(out, code);
          break;
        }
        default: --i_; fail("one of \\\" \\\\ \\/ \\b \\f \\n \\r \\t \\u");
      }
    }
  }

  double number() {
    const std::size_t start = i_;
    if (i_ < text_.size() && text_[i_] == '-') ++i_;
    while (i_ < text_.size() && (std::isdigit(static_cast<unsigned char>(text_[i_])) || text_[i_] == '.' ||
                                 text_[i_] == 'e' || text_[i_] == 'E' || text_[i_] == '+' || text_[i_] == '-'))
      ++i_;
    double v = 0.0;
    const auto [end, ec] = std::from_chars(text_.data() + start, text_.data() + i_, v);
    if (i_ == start || ec != std::errc() || end != text_.data() + i_) {
      i_ = start;
      fail("a value (an object, array, string, number, true, false or null)");
    }
    return v;
  }

  std::string_view text_;
  std::size_t i_ = 0;
};

}  // namespace

const Value* Value::find(std::string_view key) const {
  for (const auto& [name, value] : members_)
    if (name == key) return &value;
  return nullptr;
}

std::string Value::describe() const {
  switch (kind_) {
    case Kind::Null: return "null";
    case Kind::Bool: return boolean_ ? "true" : "false";
    case Kind::Number: {
      std::string n;
      appendNumber(n, number_);
      return "the number " + n;
    }
    case Kind::String: return "the string " + quoted(string_);
    case Kind::Array: return "an array";
    case Kind::Object: return "an object";
  }
  return "a value";
}

Value Value::makeBool(bool b) {
  Value v;
  v.kind_ = Kind::Bool;
  v.boolean_ = b;
  return v;
}
Value Value::makeNumber(double n) {
  Value v;
  v.kind_ = Kind::Number;
  v.number_ = n;
  return v;
}
Value Value::makeString(std::string s) {
  Value v;
  v.kind_ = Kind::String;
  v.string_ = std::move(s);
  return v;
}
Value Value::makeArray(std::vector<Value> items) {
  Value v;
  v.kind_ = Kind::Array;
  v.items_ = std::move(items);
  return v;
}
Value Value::makeObject(std::vector<std::pair<std::string, Value>> members) {
  Value v;
  v.kind_ = Kind::Object;
  v.members_ = std::move(members);
  return v;
}

Value parse(std::string_view text) { return Parser(text).document(); }

}  // namespace cobra::studio::json
