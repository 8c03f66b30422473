#include "cobra/sim/mujoco_puma260.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "cobra/text/number.hpp"

namespace cobra::sim {
namespace {

std::string number(double value) { return text::number(value, 3); }

/// MuJoCo's multi-line messages on one line.
std::string oneLine(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

KDL::Vector vector(const mjtNum* v) { return {v[0], v[1], v[2]}; }

KDL::Rotation rotation(const mjtNum* m) {
  return {m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8]};  // both row-major
}

/// Distance (m) from point `p` to the solid cylinder `c`.
double distanceToCylinder(const KDL::Vector& p, const CylinderSurface& c) {
  const KDL::Vector r = p - c.centre;
  const double along = KDL::dot(r, c.axis);
  const double radial = (r - along * c.axis).Norm();
  const double out_radial = std::max(0.0, radial - c.radius);
  const double out_axial = std::max(0.0, std::abs(along) - c.half_length);
  return std::hypot(out_radial, out_axial);
}

class Checker {
 public:
  Checker(const std::string& path, const mjModel* m) : path_(path), m_(m) {}

  [[noreturn]] void fail(const std::string& what) const { throw std::invalid_argument(path_ + ": " + what); }

  int id(int type, const char* name, const char* kind, const char* role) const {
    const int i = mj_name2id(m_, type, name);
    if (i < 0) fail(std::string("no ") + kind + " '" + name + "' (" + role + "); the Puma 260 world needs it");
    return i;
  }

 private:
  const std::string& path_;
  const mjModel* m_;
};

}  // namespace

MujocoPuma260World::MujocoPuma260World(const std::string& path) : path_(path) {
  char error[1000] = "";
  model_ = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  if (model_ == nullptr) {
    throw std::invalid_argument(path + ": cannot load the MuJoCo model: " +
                                oneLine(error[0] != '\0' ? error : "unknown MuJoCo error"));
  }
  try {
    const Checker check(path, model_);
    const mjModel* m = model_;
    if (m->njnt != 6) {
      check.fail("has " + std::to_string(m->njnt) +
                 " joints; the Puma 260 world needs 6 hinge joints, joint1 to joint6 (DH order)");
    }
    if (m->nu != 6) {
      check.fail("has " + std::to_string(m->nu) +
                 " actuators; the Puma 260 world needs 6 motor actuators, one per joint");
    }
    for (int i = 0; i < 6; ++i) {
      const int j = check.id(mjOBJ_JOINT, mjcf_names::kJoints[i], "joint", "a joint of the arm, DH order");
      if (m->jnt_type[j] != mjJNT_HINGE) check.fail(std::string("joint '") + mjcf_names::kJoints[i] + "' is not a hinge");
      qpos_[static_cast<std::size_t>(i)] = m->jnt_qposadr[j];
      dof_[static_cast<std::size_t>(i)] = m->jnt_dofadr[j];
      int actuator = -1;
      for (int a = 0; a < m->nu; ++a) {
        if (m->actuator_trntype[a] == mjTRN_JOINT && m->actuator_trnid[2 * a] == j) actuator = a;
      }
      const bool motor = actuator >= 0 && m->actuator_dyntype[actuator] == mjDYN_NONE &&
                         m->actuator_gaintype[actuator] == mjGAIN_FIXED &&
                         m->actuator_biastype[actuator] == mjBIAS_NONE && m->actuator_gainprm[actuator * mjNGAIN] == 1.0 &&
                         m->actuator_gear[6 * actuator] == 1.0;
      if (!motor) {
        check.fail(std::string("joint '") + mjcf_names::kJoints[i] +
                   "' has no motor actuator with gear 1; the Puma 260 world needs 6 motor actuators, one per joint");
      }
      actuator_[static_cast<std::size_t>(i)] = actuator;
    }
    sensor_site_ = check.id(mjOBJ_SITE, mjcf_names::kSensorSite, "site", "the FTSens sensor frame, on the tool body");
    tool_site_ = check.id(mjOBJ_SITE, mjcf_names::kToolTipSite, "site", "the tool tip");
    flange_site_ = check.id(mjOBJ_SITE, mjcf_names::kFlangeSite, "site", "the flange, DH frame 6");
    const auto sensor = [&](const char* name, int type, const char* what) {
      const int s = check.id(mjOBJ_SENSOR, name, "sensor", what);
      if (m->sensor_type[s] != type || m->sensor_objid[s] != sensor_site_) {
        check.fail(std::string("sensor '") + name + "' is not a " + what);
      }
      return m->sensor_adr[s];
    };
    force_adr_ = sensor(mjcf_names::kForceSensor, mjSENS_FORCE, "force sensor at site 'ftsens'");
    torque_adr_ = sensor(mjcf_names::kTorqueSensor, mjSENS_TORQUE, "torque sensor at site 'ftsens'");
    tool_body_ = m->site_bodyid[sensor_site_];
    tool_mass_ = m->body_subtreemass[tool_body_];
    ball_geom_ = check.id(mjOBJ_GEOM, mjcf_names::kToolBall, "geom", "the sphere at the tool's end");
    if (m->geom_type[ball_geom_] != mjGEOM_SPHERE || m->geom_bodyid[ball_geom_] != tool_body_) {
      check.fail("geom 'tool_ball' is not a sphere on the tool body (the body of site 'ftsens')");
    }
    ball_radius_ = m->geom_size[3 * ball_geom_];
    surface_geom_ = check.id(mjOBJ_GEOM, mjcf_names::kSurface, "geom", "the curved surface, a cylinder");
    if (m->geom_type[surface_geom_] != mjGEOM_CYLINDER) check.fail("geom 'surface' is not a cylinder");

    data_ = mj_makeData(model_);
    if (data_ == nullptr) check.fail("MuJoCo could not allocate its data");
    momentum_ = std::make_unique<double[]>(static_cast<std::size_t>(m->nv));
    timestep_ = m->opt.timestep;
    setJointPositions({});
    surface_.centre = vector(data_->geom_xpos + 3 * surface_geom_);
    const mjtNum* r = data_->geom_xmat + 9 * surface_geom_;
    surface_.axis = KDL::Vector(r[2], r[5], r[8]);  // the geom's z axis
    surface_.radius = m->geom_size[3 * surface_geom_];
    surface_.half_length = m->geom_size[3 * surface_geom_ + 1];
    // Reach: shoulder axis to elbow to wrist centre to tool tip, each stretched (an upper bound of
    // the distance the tip can be from the shoulder).
    const int shoulder = mj_name2id(m, mjOBJ_JOINT, mjcf_names::kJoints[1]);
    const int elbow = mj_name2id(m, mjOBJ_JOINT, mjcf_names::kJoints[2]);
    const int wrist = mj_name2id(m, mjOBJ_JOINT, mjcf_names::kJoints[4]);
    const KDL::Vector s = vector(data_->xanchor + 3 * shoulder);
    const KDL::Vector e = vector(data_->xanchor + 3 * elbow);
    const KDL::Vector w = vector(data_->xanchor + 3 * wrist);
    const KDL::Vector t = vector(data_->site_xpos + 3 * tool_site_);
    const double reach = (e - s).Norm() + (w - e).Norm() + (t - w).Norm();
    const double distance = distanceToCylinder(s, surface_);
    if (distance > reach) {
      check.fail("the surface is " + number(distance) + " m from the shoulder, beyond the arm's reach of " +
                 number(reach) + " m (geom 'surface' centred at (" + number(surface_.centre.x()) + ", " +
                 number(surface_.centre.y()) + ", " + number(surface_.centre.z()) + ") m)");
    }
    sensor_to_tool_ = sensorPose().Inverse() * toolPose();
    flange_to_sensor_ = flangePose().Inverse() * sensorPose();
  } catch (...) {
    if (data_ != nullptr) mj_deleteData(data_);
    mj_deleteModel(model_);
    throw;
  }
}

MujocoPuma260World::~MujocoPuma260World() {
  mj_deleteData(data_);
  mj_deleteModel(model_);
}

double MujocoPuma260World::time() const noexcept { return data_->time; }

void MujocoPuma260World::setJointPositions(const std::array<double, 6>& q) noexcept {
  for (std::size_t i = 0; i < 6; ++i) {
    data_->qpos[qpos_[i]] = q[i];
    data_->qvel[dof_[i]] = 0.0;
  }
  mj_forward(model_, data_);
}

void MujocoPuma260World::setMotorTorque(int joint, double newton_metre) noexcept {
  data_->ctrl[actuator_[static_cast<std::size_t>(joint)]] = newton_metre;
}

void MujocoPuma260World::setBrake(int joint, bool engaged, double torque) noexcept {
  brake_[static_cast<std::size_t>(joint)] = engaged ? std::max(0.0, torque) : 0.0;
}

void MujocoPuma260World::integrate(double h) noexcept {
  if (!std::isfinite(h) || h <= 0.0) return;
  model_->opt.timestep = h;
  mj_step1(model_, data_);  // kinematics, velocities, bias and passive forces of this state
  mj_mulM(model_, data_, momentum_.get(), data_->qvel);
  for (std::size_t i = 0; i < 6; ++i) {
    const int dof = dof_[i];
    const double hold = data_->qfrc_bias[dof] - data_->qfrc_passive[dof] - momentum_[static_cast<std::size_t>(dof)] / h;
    data_->qfrc_applied[dof] = std::clamp(hold, -brake_[i], brake_[i]);
  }
  mj_step2(model_, data_);
}

void MujocoPuma260World::step(double dt) noexcept {
  if (!std::isfinite(dt) || dt <= 0.0) return;
  const int n = std::max(1, static_cast<int>(std::ceil(dt / timestep_ - 1e-9)));
  for (int k = 0; k < n; ++k) integrate(dt / n);
}

int MujocoPuma260World::warningCount() const noexcept {
  int total = 0;
  for (int i = 0; i < mjNWARNING; ++i) total += data_->warning[i].number;
  return total;
}

double MujocoPuma260World::jointPosition(int joint) const noexcept {
  return data_->qpos[qpos_[static_cast<std::size_t>(joint)]];
}
double MujocoPuma260World::jointVelocity(int joint) const noexcept {
  return data_->qvel[dof_[static_cast<std::size_t>(joint)]];
}
double MujocoPuma260World::biasTorque(int joint) const noexcept {
  return data_->qfrc_bias[dof_[static_cast<std::size_t>(joint)]];
}

KDL::Wrench MujocoPuma260World::sensorWrench() const noexcept {
  const mjtNum* f = data_->sensordata + force_adr_;
  const mjtNum* t = data_->sensordata + torque_adr_;
  return {KDL::Vector(-f[0], -f[1], -f[2]), KDL::Vector(-t[0], -t[1], -t[2])};
}

KDL::Frame MujocoPuma260World::sitePose(int site) const noexcept {
  return {rotation(data_->site_xmat + 9 * site), vector(data_->site_xpos + 3 * site)};
}
KDL::Frame MujocoPuma260World::sensorPose() const noexcept { return sitePose(sensor_site_); }
KDL::Frame MujocoPuma260World::flangePose() const noexcept { return sitePose(flange_site_); }
KDL::Frame MujocoPuma260World::toolPose() const noexcept { return sitePose(tool_site_); }

double MujocoPuma260World::contactForce() const noexcept {
  double total = 0.0;
  for (int i = 0; i < data_->ncon; ++i) {
    const mjContact& c = data_->contact[i];
    const bool surface = c.geom1 == surface_geom_ || c.geom2 == surface_geom_;
    const int other = c.geom1 == surface_geom_ ? c.geom2 : c.geom1;
    if (!surface || model_->geom_bodyid[other] != tool_body_) continue;
    mjtNum force[6];
    mj_contactForce(model_, data_, i, force);
    total += force[0];  // the normal component (contact frame)
  }
  return total;
}

double MujocoPuma260World::penetration() const noexcept {
  const KDL::Vector r = vector(data_->geom_xpos + 3 * ball_geom_) - surface_.centre;
  const double along = KDL::dot(r, surface_.axis);
  if (std::abs(along) > surface_.half_length) return 0.0;
  const double radial = (r - along * surface_.axis).Norm();
  return std::max(0.0, surface_.radius + ball_radius_ - radial);
}

namespace {

/// The drive models with each velocity loop tuned for the joint's inertia at `world`'s current
/// position (MuJoCo's mass-matrix diagonal, armature included).
Puma260ArmModel tunedTo(const mjModel* m, const mjData* d, Puma260ArmModel model) {
  validate(model);
  for (int i = 0; i < 6; ++i) {
    const int j = mj_name2id(m, mjOBJ_JOINT, mjcf_names::kJoints[i]);
    model.drives[static_cast<std::size_t>(i)].inertia = d->qM[m->dof_Madr[m->jnt_dofadr[j]]];
  }
  return model;
}

std::array<Cia402Drive, 6> drivesAt(const Puma260ArmModel& model, const std::array<double, 6>& q) {
  return {Cia402Drive(model.drives[0], q[0]), Cia402Drive(model.drives[1], q[1]), Cia402Drive(model.drives[2], q[2]),
          Cia402Drive(model.drives[3], q[3]), Cia402Drive(model.drives[4], q[4]), Cia402Drive(model.drives[5], q[5])};
}

std::unique_ptr<MujocoPuma260World> loadAt(const std::string& path, const std::array<double, 6>& initial) {
  for (std::size_t i = 0; i < 6; ++i) {
    if (!std::isfinite(initial[i])) {
      throw std::invalid_argument("Puma 260 MuJoCo arm: initial position of joint " + std::to_string(i + 1) +
                                  " is not finite (rad)");
    }
  }
  auto world = std::make_unique<MujocoPuma260World>(path);
  world->setJointPositions(initial);
  return world;
}

}  // namespace

Puma260ArmModel MujocoPuma260Arm::defaultDrives() {
  Puma260ArmModel model = Puma260ArmModel::defaults();
  for (Cia402DriveModel& drive : model.drives) {
    drive.velocity_bandwidth = 2.0 * 3.141592653589793 * 10.0;
    drive.position_gain = 30.0;
  }
  return model;
}

MujocoPuma260Arm::MujocoPuma260Arm(const std::string& path, const Puma260ArmModel& drives,
                                   const std::array<double, 6>& initial)
    : world_(loadAt(path, initial)),
      model_(tunedTo(world_->model(), world_->data(), drives)),
      drives_(drivesAt(model_, initial)) {}

void MujocoPuma260Arm::step(double dt) noexcept {
  if (!std::isfinite(dt) || dt <= 0.0) return;
  MujocoPuma260World& w = *world_;
  for (Cia402Drive& d : drives_) d.beginCycle();
  const int n = std::max(1, static_cast<int>(std::ceil(dt / w.timestep() - 1e-9)));
  const double h = dt / n;
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < 6; ++i) {
      Cia402Drive& d = drives_[static_cast<std::size_t>(i)];
      w.setMotorTorque(i, d.controlTorque(h, w.jointPosition(i), w.jointVelocity(i)));
      w.setBrake(i, !d.powered(), model_.brake_torque);
    }
    w.integrate(h);
  }
  for (int i = 0; i < 6; ++i) drives_[static_cast<std::size_t>(i)].endCycle(dt, w.jointPosition(i), w.jointVelocity(i));
}

}  // namespace cobra::sim
