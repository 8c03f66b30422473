#include "cobra/core/operation.hpp"

#include "cobra/core/component.hpp"

namespace cobra::core {

std::string OperationBase::signature() const {
  std::string text = (result_ ? std::string(result_->name) : std::string("void")) + " " + name_ + "(";
  for (std::size_t i = 0; i < arguments_.size(); ++i) {
    const ArgumentInfo& a = arguments_[i];
    if (i > 0) text += ", ";
    text += std::string(a.type->name);
    if (!a.name.empty()) text += " " + a.name;
    if (!a.unit.empty()) text += " [" + a.unit + "]";
  }
  return text + ")";
}

std::string OperationBase::where() const {
  return (owner_ ? "component '" + owner_->name() + "': " : std::string()) + "operation '" + signature() + "'";
}

OperationBase& OperationBase::arg(std::string name, std::string unit, std::string doc) {
  for (ArgumentInfo& a : arguments_) {
    if (a.name.empty()) {
      a.name = std::move(name);
      a.unit = std::move(unit);
      a.doc = std::move(doc);
      return *this;
    }
  }
  throw Error(where() + " has " + std::to_string(arguments_.size()) + " argument(s), all already named; cannot add '" +
              name + "'");
}

namespace {
std::string typeNameOf(const std::any& value) {
  if (!value.has_value()) return "nothing";
  for (const TypeInfo* info : TypeRegistry::all())
    if (info->id == std::type_index(value.type())) return std::string(info->name);
  if (value.type() == typeid(const char*)) return "string";
  return std::string("unregistered type ") + value.type().name();
}
}  // namespace

void OperationBase::throwArgumentError(std::size_t index, const std::any& given) const {
  const ArgumentInfo& a = arguments_[index];
  throw Error(where() + ": argument " + std::to_string(index + 1) + (a.name.empty() ? "" : " ('" + a.name + "')") +
              " must be a " + std::string(a.type->name) + ", got a " + typeNameOf(given));
}

void OperationBase::throwParseError(std::size_t index, const std::string& given) const {
  const ArgumentInfo& a = arguments_[index];
  throw Error(where() + ": argument " + std::to_string(index + 1) + (a.name.empty() ? "" : " ('" + a.name + "')") +
              " must be a " + std::string(a.type->name) + ": cannot read \"" + given + "\"; expected " +
              std::string(a.type->format));
}

std::any OperationBase::invoke(const std::vector<std::any>& arguments) {
  if (arguments.size() != arguments_.size())
    throw Error(where() + " expects " + std::to_string(arguments_.size()) + " argument(s), got " +
                std::to_string(arguments.size()));
  std::any result;
  auto run = [&] {
    try {
      result = call(arguments);
    } catch (const Error&) {
      throw;
    } catch (const std::exception& e) {
      throw Error(where() + " failed: " + e.what());
    } catch (...) {
      throw Error(where() + " failed: unknown exception");
    }
  };
  if (thread_ == ExecutionThread::Own && owner_ != nullptr) {
    owner_->runBetweenSteps(run);
  } else {
    run();
  }
  return result;
}

std::string OperationBase::invokeFromText(const std::vector<std::string>& arguments) {
  if (arguments.size() != arguments_.size())
    throw Error(where() + " expects " + std::to_string(arguments_.size()) + " argument(s), got " +
                std::to_string(arguments.size()));
  return printResult(invoke(parseArguments(arguments)));
}

}  // namespace cobra::core
