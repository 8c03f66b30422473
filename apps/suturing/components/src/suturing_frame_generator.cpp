#include "cobra/components/suturing/suturing_frame_generator.hpp"


namespace cobra::components {
namespace {

/// The tool's pose at `p` over a stitch frame (x along the cut, z out of the skin): x along the
/// cut, z into the skin.
KDL::Frame toolAt(const KDL::Rotation& stitch, const KDL::Vector& p) {
  return KDL::Frame(stitch * KDL::Rotation::RotX(KDL::PI), p);
}

}  // namespace

const task::TableVocabulary& SuturingFrameGenerator::suturingVocabulary() {
  static const task::TableVocabulary words{
      {"right", "left"}, {"right_edge", "left_edge", "centre", "pull", "aside", "hook", "push"}};
  return words;
}

SuturingFrameGenerator::SuturingFrameGenerator(std::string name)
    : StateTableFrameGenerator(std::move(name), "SuturingFrameGenerator",
                               "Suturing Frame Generator (thesis §5.5): the goal poses of the Endo Stitch and the stick "
                               "for the current task state, from the current stitch's targets and a state table",
                               suturingVocabulary(),
                               {MeasuredPort{"rightMeasPose", "measured Endo Stitch tip pose, world"},
                                MeasuredPort{"leftMeasPose", "measured stick tip pose, world"}}) {
  for (auto* p : {&pull_offset_, &aside_offset_, &hook_offset_, &push_offset_}) addProperty(*p);
  addProperty(right_half_state_);
  addProperty(left_half_state_);
  addPort(right_stitch_);
  addPort(left_stitch_);
}

bool SuturingFrameGenerator::startHook() {
  have_stitch_ = {false, false};
  last_half_ = 0;
  resetAnswers();
  return true;
}

void SuturingFrameGenerator::readTaskInputs() {
  if (right_stitch_.read(stitch_[0]) != core::FlowStatus::NoData) have_stitch_[0] = true;
  if (left_stitch_.read(stitch_[1]) != core::FlowStatus::NoData) have_stitch_[1] = true;
}

void SuturingFrameGenerator::taskStateRead(std::string_view path) {
  if (task::pathContains(path, right_half_state_())) last_half_ = 0;
  else if (task::pathContains(path, left_half_state_())) last_half_ = 1;
}

task::DatumSource::Outcome SuturingFrameGenerator::resolveTaskDatum(const task::Datum& datum, std::size_t,
                                                                    KDL::Frame& pose, const char*& why) {
  if (!have_stitch_[0] || !have_stitch_[1]) {
    why = "no stitch planned yet (rightStitchPose and leftStitchPose)";
    return Outcome::Missing;
  }
  const KDL::Rotation& frame = stitch_[0].M;
  const KDL::Vector centre = (stitch_[0].p + stitch_[1].p) * 0.5;
  // The last half's frame: y outward from the wound on its side (-y of the stitch frame on the right).
  const auto fromEdge = [&](const KDL::Vector& offset) {
    const double outward = last_half_ == 0 ? -1.0 : 1.0;
    return stitch_[last_half_].p + frame * KDL::Vector(offset.x(), outward * offset.y(), offset.z());
  };
  if (datum.name == "right_edge") pose = toolAt(frame, stitch_[0].p);
  else if (datum.name == "left_edge") pose = toolAt(frame, stitch_[1].p);
  else if (datum.name == "centre") pose = toolAt(frame, centre);
  else if (datum.name == "pull") pose = toolAt(frame, centre + frame * pull_offset_());
  else if (datum.name == "aside") pose = toolAt(frame, centre + frame * aside_offset_());
  else if (datum.name == "hook") pose = toolAt(frame, fromEdge(hook_offset_()));
  else pose = toolAt(frame, fromEdge(push_offset_()));  // "push": the parser admits no other name
  return Outcome::Resolved;
}

}  // namespace cobra::components
