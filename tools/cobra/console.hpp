#pragma once
// The command interpreter of `cobra console`, in the spirit of OROCOS' TaskBrowser: browse the
// components of a deployment, read and write ports, set properties, call operations, send
// events, trace ports, drive lifecycles and switch deployments/configurations.
//
// The interpreter knows nothing about terminals: `execute` takes one line and writes its answer
// to a stream, `complete` lists completions for the word being typed. console_terminal.cpp puts
// libedit (line editing, history, tab completion) in front of it.

#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "cobra/core/core.hpp"
#include "cobra/deploy/configurator.hpp"
#include "cobra/deploy/lua_deployer.hpp"

namespace cobra::tools {

class Console {
 public:
  /// `configurator` and `deployer` must outlive the console. Answers go to `out`.
  Console(deploy::Configurator& configurator, deploy::LuaDeployer& deployer, std::ostream& out);
  ~Console();
  Console(const Console&) = delete;
  Console& operator=(const Console&) = delete;

  /// Runs one command line. Errors are printed ("error: ..."), never thrown.
  /// @return false when the line asked to quit.
  bool execute(std::string_view line);

  /// Completions of the word that ends `line` (what is left of the cursor), each a whole word.
  std::vector<std::string> complete(std::string_view line) const;

  /// "cobra> " at the top, "cobra:Name> " inside a component.
  std::string prompt() const;

  /// Set by a signal handler: a running `trace` stops at the next sample or poll.
  static void interrupt();

 private:
  struct Command;
  static const std::vector<Command>& commands();

  void run(const std::vector<std::string>& words, std::string_view line);
  void runExpression(std::string_view line);

  void help(const std::vector<std::string>& words);
  void list(const std::vector<std::string>& words);
  void changeComponent(const std::vector<std::string>& words);
  void readPort(const std::vector<std::string>& words);
  void writePort(const std::vector<std::string>& words);
  void getProperty(const std::vector<std::string>& words);
  void setProperty(const std::vector<std::string>& words);
  void callOperation(const std::string& path, const std::vector<std::string>& arguments);
  void sendEvent(const std::vector<std::string>& words);
  void trace(const std::vector<std::string>& words);
  void lifecycle(const std::vector<std::string>& words);
  void step(const std::vector<std::string>& words);
  void showTime();
  void listDeployments();
  void apply(const std::vector<std::string>& words);
  void runLua(std::string_view line);
  void load(const std::vector<std::string>& words);

  /// The component `name` names ("" or "." = the current one). @throws core::Error.
  core::Component& component(std::string_view name) const;
  /// Splits "Comp.member" or "member" (in the current component). @throws core::Error.
  std::pair<core::Component*, std::string> member(std::string_view path) const;
  core::PortBase& port(std::string_view path) const;
  core::PropertyBase& property(std::string_view path) const;
  /// `port` if it is an output, else the component output that feeds the input `port`. @throws core::Error.
  core::OutputPortBase& sourceOf(core::PortBase& port) const;
  /// An input port of the console connected to the output `port` (or to what feeds the input
  /// `port`), made on first use and kept so later reads see every new sample.
  core::InputPortBase& probe(core::PortBase& port);
  /// An output port of the console connected to the input `port`, made on first use.
  core::OutputPortBase& feeder(core::PortBase& port);
  /// Now on the deployment's clock, in s.
  double now() const;

  deploy::Configurator& configurator_;
  deploy::LuaDeployer& deployer_;
  std::ostream& out_;
  std::string current_;  // the component `cd` went into, "" at the top
  std::map<std::string, std::unique_ptr<core::InputPortBase>> probes_;    // by watched output "C.p"
  std::map<std::string, std::unique_ptr<core::OutputPortBase>> feeders_;  // by fed input "C.p"
};

/// Splits a command line into words: blanks separate, "double quotes" and [brackets] group
/// (so `write C.in [1, 2, 3]` has three words), and `#` starts a comment.
std::vector<std::string> splitCommandLine(std::string_view line);

}  // namespace cobra::tools
