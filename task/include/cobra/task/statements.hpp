#pragma once
/// @file
/// The line format of cobra's task data files (state tables; the applications' plans and scripts):
/// one statement per line, `#` starts a comment, words separated by blanks, then parameters as
/// key=value, vectors as X,Y,Z. Errors name "SOURCE:LINE". Core-free: KDL geometry only.

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <kdl/frames.hpp>

namespace cobra::task {

/// One statement: its words and key=value parameters, with where it came from. Every accessor
/// throws std::invalid_argument "SOURCE:LINE: message" on a missing or malformed value.
struct Statement {
  std::string where;  ///< "source:line"
  int line = 0;
  std::vector<std::string> words;
  std::map<std::string, std::string> params;
  std::map<std::string, bool> used;

  [[noreturn]] void fail(const std::string& message) const;

  bool has(const std::string& key) const { return params.count(key) != 0; }
  /// The text of `key` (marks it used). @throws when the statement lacks it.
  const std::string& raw(const std::string& key);
  double number(const std::string& key, const char* unit);
  double number(const std::string& key, double fallback, const char* unit);
  double parseNumber(const std::string& key, std::string_view text, const char* unit) const;
  KDL::Vector vector(const std::string& key, const char* unit);
  /// `xyz=X,Y,Z [rpy=R,P,Y]` (m, rad; KDL's RPY).
  KDL::Frame frame();
  double positive(const std::string& key, const char* unit);
  /// Checks that every parameter was used and that there are `count` words (statement included).
  void finish(std::size_t count, const char* usage) const;
};

/// The statements of `text`; `source` names it in errors.
/// @throws std::invalid_argument "SOURCE:LINE: message" (a word after the parameters, a key twice).
std::vector<Statement> statements(std::string_view text, std::string_view source);

/// The shortest decimal that parses back to exactly `value` (a printed file parses to the same numbers).
std::string printNumber(double value);
/// "xyz=X,Y,Z rpy=R,P,Y", numbers as printNumber.
std::string printFrame(const KDL::Frame& frame);
/// "X,Y,Z", numbers as printNumber.
std::string printVector(const KDL::Vector& v);

/// Reads a file. @throws std::invalid_argument naming the path when it cannot be read.
std::string readText(const std::string& path);

}  // namespace cobra::task
