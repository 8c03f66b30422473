#pragma once
/// @file
/// The data of the puncturing task (thesis §4.2, §4.5.5): preoperative information, the
/// cryoablation plan, the ultrasound probe plan, the vocabulary of the Puncturing Frame
/// Generator's state table and the scripted surgeon, each read from a small text format (apps/puncturing/
/// README.md). Core-free: KDL geometry only.
///
/// Frame A (abdomen) is the simulated phantom's frame P (sim/README.md): the undeformed skin is
/// the plane z = 0, tissue below it (z < 0), world z up. Plans are in frame A; the Frame
/// Generator maps them to the task frame T with the registered pose of A in T (`abdomenFrame`).
/// A needle pose is its tip frame with z along the needle, pointing into the body; a probe pose
/// has z along the beam and x along the array, its imaging plane is its x-z plane (as in sim/).
/// Units: m, rad.

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <kdl/frames.hpp>

#include "cobra/task/state_table.hpp"
#include "cobra/task/statements.hpp"

namespace cobra::puncturing {

/// A forbidden region (rib, vessel, ...): a capsule around segment a-b, a sphere when a == b.
struct ForbiddenRegion {
  std::string name;
  KDL::Vector a, b;     ///< m, frame A
  double radius = 0.0;  ///< m, > 0
};

/// What imaging and registration say about the patient.
struct PreoperativeInfo {
  KDL::Frame abdomen_in_task = KDL::Frame::Identity();  ///< nominal registration of A in T (m, rad)
  KDL::Vector tumour_center;                            ///< m, frame A, below the skin
  double tumour_radius = 0.0;                           ///< m, > 0
  std::vector<ForbiddenRegion> forbidden;
  KDL::Vector entry_center;                             ///< m, frame A, on the skin (z = 0)
  double entry_radius = 0.0;                            ///< m, > 0: the disc where needles may enter
};

/// One planned needle: where it crosses the skin and where its tip must end, frame A.
struct PlannedNeedle {
  std::string name;
  KDL::Vector entry;   ///< m, on the skin
  KDL::Vector target;  ///< m, inside the tumour
  double roll = 0.0;   ///< rad, the tip frame's rotation about the needle axis
  int line = 0;        ///< line of the plan file (for messages)
};

/// One planned probe pose, for the needle of the same name: the probe face on the skin, frame A.
struct PlannedProbe {
  std::string needle;
  KDL::Frame pose;
  int line = 0;
};

/// The state table (thesis §4.5.5) is the framework's (cobra/task/state_table.hpp): the
/// puncturing table is one with the vocabulary below.
using task::Datum;
using task::DatumMotion;
using task::StateRow;
using task::StateTable;
using task::TableVocabulary;
using task::alongZ;
using task::parseStateTable;
using task::pathContains;
using task::readText;

/// The puncturing table's words: arms needle and probe; datums entry, target, probe, next_entry,
/// next_target, next_probe.
const TableVocabulary& puncturingVocabulary();

/// A surgeon's scripted action: emit `event` `at` s after the start, or `after` s after chart
/// `chart` ("needle" or "us") entered a state whose path contains `state`, at most `times` times.
struct SurgeonAction {
  enum class Trigger { At, OnState };
  Trigger trigger = Trigger::At;
  double at = 0.0;        ///< s (Trigger::At)
  std::string chart;      ///< "needle" or "us" (Trigger::OnState)
  std::string state;      ///< path components (Trigger::OnState)
  double after = 0.0;     ///< s (Trigger::OnState)
  int times = 0;          ///< 0: every time
  std::string event;      ///< one of surgeonEvents()
  int line = 0;
};

struct SurgeonScript {
  std::vector<SurgeonAction> actions;
};

/// The confirmations and choices a surgeon gives (apps/puncturing/README.md).
const std::vector<std::string>& surgeonEvents();

/// A whole plan: what the Frame Generator loads.
struct PuncturingPlan {
  PreoperativeInfo preoperative;
  std::vector<PlannedNeedle> needles;
  std::vector<PlannedProbe> probes;  ///< probes[i] belongs to needles[i]
};

/// The parsers. `source` names the text in errors, which read "SOURCE:LINE: message".
/// @throws std::invalid_argument on syntax errors, unknown statements or keys, values out of range.
PreoperativeInfo parsePreoperative(std::string_view text, std::string_view source);
std::vector<PlannedNeedle> parseCryoPlan(std::string_view text, std::string_view source);
std::vector<PlannedProbe> parseProbePlan(std::string_view text, std::string_view source);
StateTable parseStateTable(std::string_view text, std::string_view source);  ///< puncturingVocabulary()
SurgeonScript parseSurgeonScript(std::string_view text, std::string_view source);

/// The text forms: parse(print(x)) == x, numbers exactly (printed as their shortest exact decimal),
/// rotations (printed as roll, pitch, yaw) to within rounding (1e-9 rad).
std::string print(const PreoperativeInfo& info);
std::string printCryoPlan(const std::vector<PlannedNeedle>& needles);
std::string printProbePlan(const std::vector<PlannedProbe>& probes);

/// Parses the three files and checks them against each other (validate()).
/// @throws std::invalid_argument "FILE:LINE: message".
PuncturingPlan loadPlan(const std::string& preoperative_file, const std::string& cryo_plan_file,
                        const std::string& probe_plan_file);

/// Checks that the plan is feasible, naming the file and line of what is not: every needle enters
/// from above (within 60° of -z) through the entry disc, its tip lies in the tumour, its path
/// keeps `clearance` m from every forbidden region and its inserted length is below
/// `needle_length` m; every needle has exactly one probe pose, on the skin, beam pointing into the
/// body, whose imaging plane contains the needle (within 1 mm) and shows the target.
/// @throws std::invalid_argument.
void validate(const PuncturingPlan& plan, std::string_view cryo_source, std::string_view probe_source,
              double needle_length = 0.15, double clearance = 0.002);

/// The tip frame of a needle at its target (z along the needle, into the body), frame A.
KDL::Frame needleTargetPose(const PlannedNeedle& needle);
/// The same orientation with the tip at the skin entry point, frame A.
KDL::Frame needleEntryPose(const PlannedNeedle& needle);

/// Shortest distance (m) from segment p-q to the surface of `region` (< 0: inside).
double distanceToRegion(const KDL::Vector& p, const KDL::Vector& q, const ForbiddenRegion& region);

/// Whether `name` is a datum of the current needle's plan (entry, target, probe) or of the next
/// one's (next_entry, next_target, next_probe); `next` says which.
bool planDatum(std::string_view name, bool& next);

}  // namespace cobra::puncturing
