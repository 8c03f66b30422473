#pragma once
/// @file
/// What an application declares for the runner: the `run = { ... }` table of its entry file and
/// the entries of a faults file, read from Lua into plain structs (format: run/README.md). Every
/// entry keeps the file:line it was written at, so that the runner's errors name it. Names of
/// components, ports and states are checked by the runner against the deployment, not here.

#include <map>
#include <memory>
#include <string>
#include <vector>

struct lua_State;

namespace cobra::run {

/// Where an entry is written: "file:line".
struct Where {
  std::string file;
  int line = 0;
  std::string text() const { return file + ":" + std::to_string(line); }
};

/// A task chart whose states end the run: the Supervisor `supervisor` runs it.
struct ChartSpec {
  std::string name;        ///< short name used in logs, triggers and tracking ("needle")
  std::string supervisor;  ///< component name of its Supervisor
  std::string done;        ///< state path that completes the chart
  std::string safe_stop;   ///< state path of its safe stop ("" when none)
  std::string scope;       ///< deployment scope whose switches are logged ("" = the default scope)
  std::vector<std::string> sources;  ///< event sources (name prefixes) whose events this chart receives
  Where where;
};

/// When an action or fault fires: an event (from `source` when given), a chart entering a state
/// whose path starts with `state`, or a time [s].
struct Trigger {
  enum class Kind { Event, State, Time } kind = Kind::Time;
  std::string event, source;  ///< Event
  std::string chart, state;   ///< State ("needle:root.WaitCryoCycle")
  double time = 0.0;          ///< Time [s]
  std::string text() const;
};

/// One action of `run.actions` or one fault of a faults file: `after` s after its trigger, call
/// an operation, write a port, set a property, run deployer Lua or make a component's next
/// updateHook throw (`throw = "Comp"`, core/fault_injection.hpp); once unless `repeat`.
struct ActionSpec {
  Trigger on;
  double after = 0.0;  ///< s
  bool repeat = false;
  /// s: > 0 plays it again every `every` s after its first play, until the run ends (e.g. a
  /// bus frame lost at random every cycle); logged once, at its first play.
  double every = 0.0;
  /// With `every`: each period's play happens with this probability (0..1), drawn from a
  /// generator seeded with `seed` (a run is reproduced exactly); 1: always.
  double chance = 1.0;
  unsigned seed = 1;
  enum class Kind { Call, Write, Set, Lua, Throw } kind = Kind::Call;
  std::string component;  ///< Call/Write/Set/Throw
  std::string member;     ///< operation, port or property
  std::string text;       ///< "call Patient.startFreeze", for logs
  int lua_ref = -1;       ///< the entry's table in the Lua registry (value, args, code)
  Where where;
};

/// A port recorded every `period`: "Comp.port".
struct RecordSpec {
  double period = 0.01;  ///< s
  std::vector<std::pair<std::string, Where>> ports;
};

/// A path of an xy figure: column `y` against column `x` at the same sample times (e.g. a tool's
/// y and z: its path in the y-z plane), with labelled marks where charts entered states.
struct PathSpec {
  std::string label;
  std::string x, y;  ///< columns
  bool dashed = false;
  /// A point of the path labelled `label`, at the first sample at or after the time chart `chart`
  /// first entered a state whose full path starts with `state` (the last sample when there is none
  /// after it; no mark when the chart never entered such a state).
  struct Mark {
    std::string label, chart, state;
  };
  std::vector<Mark> marks;
};

/// A figure of the report: series are recorded columns ("Comp.port" for a scalar,
/// "Comp.port.z" for a field, "tracking.NAME.mm", ...), against time or against column `x`; or
/// paths, each with its own x and y columns.
struct PlotSpec {
  std::string title;
  std::string unit;    ///< of the series (axis label)
  std::string x;       ///< column of the x axis; "" = time
  std::string x_unit;  ///< of x
  std::vector<std::string> series;
  std::vector<PathSpec> paths;
  /// Paths only: drawn from when chart `from_chart` first entered a state whose path starts with
  /// `from_state` ("" = from the start), e.g. to zoom on a task's last phases.
  std::string from_chart, from_state;
  Where where;
};

/// A summary value: the distance between two Frame ports' positions, or a double port, sampled
/// when a chart enters/leaves a state; or the number of events of some names.
struct SummarySpec {
  std::string name;
  std::string unit;
  double scale = 1.0;  ///< value = scale * port value (1000: m -> mm)
  enum class Kind { Distance, Port, Count } kind = Kind::Count;
  std::vector<std::string> ports;   ///< Distance: two Frame ports; Port: one double port
  std::vector<std::string> events;  ///< Count
  /// Count: an event of `events` the task causes itself where it is expected (the ultrasound
  /// losing the needle while the needle chart takes it out): heard while `chart` is in `state`
  /// (a prefix of its state path), it is counted on a row of its own ("expected task events"),
  /// not as one of `events`.
  struct Expected {
    std::string event, chart, state;
  };
  std::vector<Expected> expected;
  std::string chart, state;         ///< when: the chart enters (`leave` false) or leaves a state
  bool leave = false;
  std::string of;  ///< "Comp.operation" returning how many samples are expected (int): "2 of 2"
  bool say = false;  ///< print each sample as a progress line
  Where where;
};

/// One tool whose commanded and measured poses are compared (TrackingMonitor).
struct TrackingSpec {
  std::string name;
  std::string commanded, measured;  ///< Frame ports
  std::string joints;               ///< JntArray port of the measured joints ("" = no joint check)
  std::string max_velocity;         ///< "Comp.property" (vector, rad/s or m/s per joint), or
  std::vector<double> max_velocity_values;  ///< the limits themselves (rad/s or m/s per joint)
  std::string chart;                ///< whose state is kept with the worst figures
  std::string scope;                ///< samples count while this scope's deployment is one of:
  std::vector<std::string> counts_while;
  double accept_mm = kAcceptMm, accept_deg = kAcceptDeg;  ///< the acceptance lines of the plots
  Where where;
  static constexpr double kAcceptMm = 2.0, kAcceptDeg = 1.0;
};

/// A span during which clearance samples do not count (e.g. the needle in tissue: the port's
/// component measures that contact as a collision): from a state containing one of `from` until
/// one containing one of `to`.
struct ClearancePause {
  std::string name, chart;
  std::vector<std::string> from, to;
};

struct ClearanceSpec {
  bool declared = false;
  std::string port;                 ///< double port, m (NaN: state not measurable)
  double threshold = 0.0;           ///< m, when given as a number
  std::string threshold_operation;  ///< "Comp.operation" returning it, when given as a name
  std::vector<std::pair<std::string, std::string>> contacts;  ///< name, double port [m]
  std::vector<ClearancePause> pauses;
  /// Per pair of groups (optional, both or neither): a vector<double> port of one clearance per
  /// pair [m] (NaN: not measurable) and the "Comp.operation" naming them, comma-separated in the
  /// port's order ("macro/micro,micro/ur5"; a MotionPlanner's pairDistances and clearancePairs).
  std::string pairs, pair_names;
  Where where, pairs_where;
};

/// `run.studio`: what cobra studio shows of the run and the surgeon's inputs it offers
/// (studio/README.md). Entries are name = value tables, kept in the order of their lines.
struct StudioSpec {
  bool declared = false;
  /// The component whose planning scene is drawn (a MotionPlanner or StateValidator: the same
  /// scene it checks collisions in); "" = no scene (robots show their joints only).
  std::string scene;
  Where scene_where;
  /// A robot of the scene (its name there, "isur") and its measured joints (KDL.JntArray port).
  struct Robot {
    std::string name, joints;
    int count = 0;  ///< joints, when no scene gives the robot's model (`{ "Comp.port", joints = 6 }`)
    /// A KinematicsSolver component whose DH chain draws the robot when no scene models it
    /// (`{ "Comp.port", kinematics = "Comp" }`: its links and joint count); "" none.
    std::string kinematics;
    Where where;
  };
  std::vector<Robot> robots;
  /// Something drawn beside the robots, in the world frame (studio/README.md, "Extras"). Kinds
  /// read from ports every frame: "sphere" (centre: Frame port, radius: double port [m]), "plane"
  /// (pose: Frame port, size: width and height [m]), "points", "polyline" (`strands` lines, the
  /// port's points dealt to them in turn) and "segments" (point pairs): a vector<double> port of
  /// x y z triples [m], at most `max` points ("points" also takes a Frame port: one point). Kinds
  /// read once from a vector<double> property at setup (fixed shapes): "spheres" (x y z radius
  /// each), "capsules" and "cylinders" (the axis' end points x y z x y z, radius each) and "slabs"
  /// (top and bottom depth pairs below the x-y plane of the Frame property `frame`, each a box of
  /// width x height, or of the x and y lengths of the box `footprint` of the drawn scene) [m].
  struct Extra {
    std::string name, kind;
    std::string pose;    ///< "Comp.member" of the kind: the sphere's centre, the plane's pose, the points, the property
    std::string radius;  ///< sphere: double port [m]
    double width = 0.0, height = 0.0;  ///< plane, slabs [m]
    int max = 256;       ///< points, polyline, segments: points of a vector port shown at most
    int strands = 1;     ///< polyline: lines the points alternate between
    std::string frame;      ///< slabs: the Frame property of the skin's pose ("Comp.property")
    std::string footprint;  ///< slabs: a box object of the drawn scene giving width and height ("" = width, height)
    Where where;
  };
  std::vector<Extra> extras;
  /// Plottable columns: "Comp.port" (double) or "Comp.port.field" as run.record names them.
  std::vector<std::pair<std::string, Where>> signals;
  /// A surgeon's input: a button of the console calling `call` ("Surgeon.say") with `args`.
  struct Input {
    std::string name, label, call;
    /// The event the input makes a component send (`event = "..."`; default: its first
    /// argument, as `Surgeon.say`'s): the console offers the input when a chart waits for it.
    std::string event;
    std::vector<std::string> args;
    int lua_ref = -1;  ///< { call = , args = } in the Lua registry (played as an action)
    Where where;
  };
  std::vector<Input> inputs;
};

class Observer;

/// A section of the `run` table made into its observer by the observer registered under the
/// section's name (cobra/run/observer.hpp).
struct ObserverSection {
  std::string name;  ///< the section's key, the observer's registered name
  Where where;
  std::shared_ptr<Observer> observer;
};

/// The whole `run` table.
struct RunSpec {
  std::string title;
  std::vector<ChartSpec> charts;
  std::vector<std::string> fold;  ///< leaf state names folded into their parent in the log
  std::vector<std::string> failures;  ///< events whose last one is a safe stop's reason
  std::map<std::string, std::string> explain;  ///< failure event -> operation of its source giving why
  std::string safe_stop_reason;  ///< text added to a safe stop's reason
  double safe_stop_linger = 2.0;  ///< s the run goes on after a safe stop (the other charts stop too)
  /// s a chart may stay in one state before the run says what it waits for and what it heard
  /// there (stall_watch.hpp); 0: never. Said once per state; the time limit's reason says it too.
  double stall_notice = 30.0;
  double step = 0.001;  ///< s: the runner's observation period
  std::vector<ActionSpec> actions;
  RecordSpec record;
  std::vector<PlotSpec> plots;
  std::vector<SummarySpec> summary;
  std::vector<TrackingSpec> tracking;
  ClearanceSpec clearance;
  StudioSpec studio;
  /// Every section other than the runner's own (title, charts, fold, failures, explain,
  /// safe_stop_reason, safe_stop_linger, stall_notice, step, actions) as its observer, in the registry's order.
  /// cobra's own observers keep their typed part above (record ... studio) as well.
  std::vector<ObserverSection> observers;
};

/// Reads the global `run` of `L` (written in `file`, whose text gives the entries' lines): the
/// runner's own fields, then every other section through its registered observer.
/// @throws std::runtime_error "file:line: run.<path>: what was expected", or for a section no
///         observer is registered for "file:line: run.NAME: unknown section 'NAME'; did you mean
///         'M'? known sections: ...".
RunSpec readRunSpec(lua_State* L, const std::string& file);

/// Runs the faults file `file` in `L` (it returns a list of entries, ActionSpec's format) and
/// reads it. @throws std::runtime_error "file:line: ..." for a Lua error or a bad entry.
std::vector<ActionSpec> readFaults(lua_State* L, const std::string& file);

}  // namespace cobra::run
