#pragma once
/// @file
/// Typed, named, documented properties with units and optional range checks.

#include <concepts>
#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include "cobra/core/data_type.hpp"
#include "cobra/core/error.hpp"

namespace cobra::core {

class Component;

/// What every property has; the by-name interface used by the deployer, console and studio.
class PropertyBase {
 public:
  PropertyBase(std::string name, std::string unit, std::string doc, const TypeInfo& type)
      : name_(std::move(name)), unit_(std::move(unit)), doc_(std::move(doc)), type_(&type) {}
  virtual ~PropertyBase() = default;
  PropertyBase(const PropertyBase&) = delete;
  PropertyBase& operator=(const PropertyBase&) = delete;

  const std::string& name() const { return name_; }
  /// SI unit of the value ("m", "N/m", "s", "1" for dimensionless, "" for text and flags).
  const std::string& unit() const { return unit_; }
  const std::string& doc() const { return doc_; }
  const TypeInfo& type() const { return *type_; }
  bool isReadOnly() const { return read_only_; }
  Component* owner() const { return owner_; }

  /// The current value as text (thread-safe).
  virtual std::string valueText() const = 0;
  /// "[min, max]" when a range is set, otherwise "".
  virtual std::string rangeText() const = 0;
  /// Parses `text` and sets the value (see `Property::set`).
  /// @throws Error naming the component, the property, what was given and what was expected.
  virtual void setFromText(std::string_view text) = 0;
  /// Throws exactly the error `setFromText(text)` would, without changing anything: lets a
  /// deployer check a whole configuration before applying any of it.
  virtual void checkText(std::string_view text) const = 0;

  /// "component 'Gain': property 'k'", the start of every error message about this property.
  std::string where() const;

 protected:
  /// Runs `change` between two steps of the owner, holding the lock outside readers take.
  void applyChange(const std::function<void()>& change);
  /// Runs `read` under the lock that `applyChange` holds.
  void readLocked(const std::function<void()>& read) const;
  [[noreturn]] void throwReadOnly() const;

  bool read_only_ = false;

 private:
  friend class Component;
  std::string name_;
  std::string unit_;
  std::string doc_;
  const TypeInfo* type_;
  Component* owner_ = nullptr;
};

/// A property of type T. The owner's hooks read it with `get()` (real-time safe: no lock, no
/// copy); everyone else sets it with `set()` (or by name through the component), which checks
/// it and applies it between two updates of a running component, never during one.
template <RegisteredDataType T>
class Property final : public PropertyBase {
 public:
  /// @param unit SI unit of the value, documented on every property.
  Property(std::string name, T initial, std::string unit, std::string doc)
      : PropertyBase(std::move(name), std::move(unit), std::move(doc), typeInfo<T>()), value_(std::move(initial)) {}

  /// The value in effect. Call from the owner's hooks (or when no activity runs).
  const T& get() const { return value_; }
  const T& operator()() const { return value_; }

  /// A copy of the value, safe to call from any thread.
  T value() const {
    T copy{};
    readLocked([&] { copy = value_; });
    return copy;
  }

  /// Restricts the accepted values to [min, max]; the initial value must already be inside.
  Property& range(T min, T max)
    requires std::totally_ordered<T> && std::is_arithmetic_v<T>
  {
    if (!(min <= max)) throw Error(where() + ": range [" + printValue(min) + ", " + printValue(max) + "] is empty");
    min_ = min;
    max_ = max;
    if (!inRange(value_)) throw Error(where() + ": initial value " + printValue(value_) + " is outside " + rangeText());
    return *this;
  }

  /// Refuses every `set` from outside; the owner changes it with `setFromOwner` (status values).
  Property& readOnly() {
    read_only_ = true;
    return *this;
  }

  /// Sets the value after checking read-only and range.
  /// @throws Error naming the component and property; the value is then left unchanged.
  void set(T value) {
    check(value);
    applyChange([&] { std::swap(value_, value); });
  }

  /// Throws the error `set(value)` would, without changing anything.
  void check(const T& value) const {
    if (read_only_) throwReadOnly();
    if (!inRange(value))
      throw Error(where() + " = " + printValue(value) + " is out of range " + rangeText() +
                  (unit().empty() ? "" : " (" + unit() + ")"));
  }

  /// The owner's own write (e.g. a read-only status value); not range-checked. Call only from
  /// the owner's hooks.
  void setFromOwner(const T& value) { value_ = value; }

  std::string valueText() const override { return printValue(value()); }
  std::string rangeText() const override {
    if constexpr (std::is_arithmetic_v<T>) {
      if (min_) return "[" + printValue(*min_) + ", " + printValue(*max_) + "]";
    }
    return "";
  }
  void setFromText(std::string_view text) override { set(parseText(text)); }
  void checkText(std::string_view text) const override { check(parseText(text)); }

 private:
  T parseText(std::string_view text) const {
    T parsed{};
    if (!DataTypeTraits<T>::parse(text, parsed))
      throw Error(where() + " is a " + std::string(type().name) + ": cannot set it from \"" + std::string(text) +
                  "\"; expected " + std::string(type().format));
    return parsed;
  }

  bool inRange(const T& value) const {
    if constexpr (std::is_arithmetic_v<T>) {
      if (min_ && !(value >= *min_ && value <= *max_)) return false;  // NaN is outside too
    }
    (void)value;
    return true;
  }

  T value_;
  std::optional<T> min_;
  std::optional<T> max_;
};

}  // namespace cobra::core
