#pragma once
/// @file
/// Named, documented operations callable by name with typed arguments.

#include <any>
#include <functional>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "cobra/core/data_type.hpp"
#include "cobra/core/error.hpp"

namespace cobra::core {

class Component;

/// Where an operation runs. `Own`: in the owner's activity, between two updates (the caller
/// waits); use it for anything touching the component's state. `Client`: directly in the
/// caller's thread; only for code that is thread-safe by itself.
enum class ExecutionThread { Own, Client };

/// One argument of an operation, for signatures and error messages.
struct ArgumentInfo {
  std::string name;
  std::string unit;
  std::string doc;
  const TypeInfo* type;
};

/// Type-erased operation: what the deployer, console and scripts call.
class OperationBase {
 public:
  OperationBase(std::string name, std::string doc, ExecutionThread thread, const TypeInfo* result,
                std::vector<ArgumentInfo> arguments)
      : name_(std::move(name)), doc_(std::move(doc)), thread_(thread), result_(result), arguments_(std::move(arguments)) {}
  virtual ~OperationBase() = default;
  OperationBase(const OperationBase&) = delete;
  OperationBase& operator=(const OperationBase&) = delete;

  const std::string& name() const { return name_; }
  const std::string& doc() const { return doc_; }
  ExecutionThread thread() const { return thread_; }
  /// nullptr for void operations.
  const TypeInfo* resultType() const { return result_; }
  const std::vector<ArgumentInfo>& arguments() const { return arguments_; }
  /// e.g. "double moveTo(double position [m], double duration [s])".
  std::string signature() const;

  /// Names and documents the next argument (in order). Returns *this for chaining.
  /// @throws Error when every argument is already named.
  OperationBase& arg(std::string name, std::string unit, std::string doc);

  /// Calls the operation. Each argument must hold the argument's type exactly, or an int where
  /// a double is expected, or a `const char*` where a string is expected.
  /// @throws Error naming the component, the operation signature and the offending argument;
  /// also when the operation itself throws (its message is kept).
  std::any invoke(const std::vector<std::any>& arguments);
  /// Parses each text argument with its type's text form, calls, and prints the result ("" for
  /// void).
  std::string invokeFromText(const std::vector<std::string>& arguments);

  /// "component 'TrajGen': operation 'double moveTo(...)'".
  std::string where() const;

 protected:
  /// Converts the arguments (already count-checked) and calls; in the owner's thread or not.
  virtual std::any call(const std::vector<std::any>& arguments) = 0;
  virtual std::vector<std::any> parseArguments(const std::vector<std::string>& arguments) = 0;
  virtual std::string printResult(const std::any& result) = 0;
  [[noreturn]] void throwArgumentError(std::size_t index, const std::any& given) const;
  [[noreturn]] void throwParseError(std::size_t index, const std::string& given) const;

 private:
  friend class Component;
  std::string name_;
  std::string doc_;
  ExecutionThread thread_;
  const TypeInfo* result_;
  std::vector<ArgumentInfo> arguments_;
  Component* owner_ = nullptr;
};

namespace detail {
template <class A>
bool convertArgument(const std::any& given, A& out) {
  if (const A* exact = std::any_cast<A>(&given)) {
    out = *exact;
    return true;
  }
  if constexpr (std::is_same_v<A, double>) {
    if (const int* i = std::any_cast<int>(&given)) {
      out = *i;
      return true;
    }
  }
  if constexpr (std::is_same_v<A, std::string>) {
    if (const char* const* text = std::any_cast<const char*>(&given)) {
      out = *text;
      return true;
    }
  }
  return false;
}

template <class R>
const TypeInfo* resultTypeInfo() {
  if constexpr (std::is_void_v<R>) return nullptr;
  else return &typeInfo<R>();
}
}  // namespace detail

/// An operation with the C++ signature R(Args...).
template <class R, class... Args>
class Operation final : public OperationBase {
  static_assert((RegisteredDataType<std::decay_t<Args>> && ...),
                "cobra: every operation argument type must be registered (DataTypeTraits)");
  static_assert(std::is_void_v<R> || RegisteredDataType<R>,
                "cobra: an operation's result type must be void or registered (DataTypeTraits)");

 public:
  Operation(std::string name, std::function<R(Args...)> function, std::string doc, ExecutionThread thread)
      : OperationBase(std::move(name), std::move(doc), thread, detail::resultTypeInfo<R>(),
                      {ArgumentInfo{"", "", "", &typeInfo<std::decay_t<Args>>()}...}),
        function_(std::move(function)) {}

 protected:
  std::any call(const std::vector<std::any>& arguments) override {
    return callWith(arguments, std::index_sequence_for<Args...>{});
  }

  std::vector<std::any> parseArguments(const std::vector<std::string>& texts) override {
    std::vector<std::any> parsed;
    parseEach(texts, parsed, std::index_sequence_for<Args...>{});
    return parsed;
  }

  std::string printResult(const std::any& result) override {
    if constexpr (std::is_void_v<R>) return "";
    else return printValue(std::any_cast<const R&>(result));
  }

 private:
  template <std::size_t... I>
  std::any callWith(const std::vector<std::any>& arguments, std::index_sequence<I...>) {
    std::tuple<std::decay_t<Args>...> values;
    (convertOne<I>(arguments, std::get<I>(values)), ...);
    if constexpr (std::is_void_v<R>) {
      std::apply(function_, std::move(values));
      return {};
    } else {
      return std::any(std::apply(function_, std::move(values)));
    }
  }

  template <std::size_t I, class A>
  void convertOne(const std::vector<std::any>& arguments, A& out) {
    if (!detail::convertArgument(arguments[I], out)) throwArgumentError(I, arguments[I]);
  }

  template <std::size_t... I>
  void parseEach(const std::vector<std::string>& texts, std::vector<std::any>& parsed, std::index_sequence<I...>) {
    (parseOne<I, std::decay_t<Args>>(texts, parsed), ...);
  }

  template <std::size_t I, class A>
  void parseOne(const std::vector<std::string>& texts, std::vector<std::any>& parsed) {
    A value{};
    if (!DataTypeTraits<A>::parse(texts[I], value)) throwParseError(I, texts[I]);
    parsed.emplace_back(std::move(value));
  }

  std::function<R(Args...)> function_;
};

}  // namespace cobra::core
