#include "cobra/planning/collision_world.hpp"

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>

namespace cobra::planning {

namespace {

fcl::Transform3d toFcl(const KDL::Frame& frame) {
  fcl::Transform3d transform = fcl::Transform3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) transform.linear()(r, c) = frame.M(static_cast<unsigned>(r), static_cast<unsigned>(c));
    transform.translation()(r) = frame.p(r);
  }
  return transform;
}

KDL::Frame toKdl(const fcl::Transform3d& transform) {
  const auto& m = transform.linear();
  const auto& p = transform.translation();
  return KDL::Frame(KDL::Rotation(m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)),
                    KDL::Vector(p(0), p(1), p(2)));
}

std::shared_ptr<fcl::CollisionGeometryd> makeGeometry(const ObjectDescription& object) {
  const auto& d = object.shape.dimensions;
  switch (object.shape.kind) {
    case ShapeKind::Box: return std::make_shared<fcl::Boxd>(d[0], d[1], d[2]);
    case ShapeKind::Cylinder: return std::make_shared<fcl::Cylinderd>(d[0], d[1]);
    case ShapeKind::Capsule: return std::make_shared<fcl::Capsuled>(d[0], d[1]);
    case ShapeKind::Sphere: return std::make_shared<fcl::Sphered>(d[0]);
    case ShapeKind::Mesh: break;
  }
  TriangleMesh mesh;
  try {
    mesh = loadMesh(object.shape.mesh_path, object.shape.mesh_scale);
  } catch (const std::exception& error) {
    const std::string where = object.origin.empty() ? "" : object.origin + ": ";
    throw std::runtime_error(where + "object '" + object.name + "': " + error.what());
  }
  std::vector<fcl::Vector3d> vertices;
  vertices.reserve(mesh.vertices.size());
  for (const auto& v : mesh.vertices) vertices.emplace_back(v[0], v[1], v[2]);
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  model->beginModel();
  model->addSubModel(vertices, triangles);
  model->endModel();
  model->computeLocalAABB();
  return model;
}

/// What the last measurement of a pair of objects found: its distance [m] (< 0: never measured)
/// and how far each object had travelled then (CollisionWorld::Impl::travelled).
struct PairMemo {
  double distance = -1.0;
  double travelled_first = 0.0;
  double travelled_second = 0.0;
};

/// A pair's memo may bound it only this much [m] under its memo's distance: the narrow phase's
/// own tolerance (FCL's default distance_tolerance), so a rounding never hides a closer pair.
constexpr double kMemoSlack = 1e-6;

/// State of one broadphase distance search (FCL's callback protocol: return true to stop).
struct DistanceSearch {
  fcl::DistanceRequestd request;
  double minimum = std::numeric_limits<double>::infinity();
  double stop_below = 0.0;
  const fcl::CollisionObjectd* first = nullptr;
  const fcl::CollisionObjectd* second = nullptr;
  /// The scene's allowed contacts, as pairs of objects' user data (ObjectDescription*); and its
  /// primitive contacts when they are measured apart (nullptr otherwise).
  const std::vector<std::pair<const void*, const void*>>* allowed = nullptr;
  const std::vector<std::pair<const void*, const void*>>* primitive = nullptr;
  /// The scene's objects (an object's user data points into it): its index keys the memos.
  const ObjectDescription* objects = nullptr;
  std::size_t object_count = 0;
  std::vector<PairMemo>* memos = nullptr;  // object_count² (lower index first)
  const std::vector<double>* travelled = nullptr;
};

bool listed(const std::vector<std::pair<const void*, const void*>>* pairs, const fcl::CollisionObjectd* a,
            const fcl::CollisionObjectd* b) {
  if (pairs == nullptr) return false;
  for (const auto& [x, y] : *pairs)
    if ((a->getUserData() == x && b->getUserData() == y) || (a->getUserData() == y && b->getUserData() == x))
      return true;
  return false;
}

bool allowedContact(const DistanceSearch& search, const fcl::CollisionObjectd* a, const fcl::CollisionObjectd* b) {
  return listed(search.allowed, a, b) || listed(search.primitive, a, b);
}

std::size_t indexOf(const DistanceSearch& search, const fcl::CollisionObjectd* object) {
  return static_cast<std::size_t>(static_cast<const ObjectDescription*>(object->getUserData()) - search.objects);
}

bool distanceCallback(fcl::CollisionObjectd* a, fcl::CollisionObjectd* b, void* data, double& distance) {
  auto& search = *static_cast<DistanceSearch*>(data);
  // With a threshold, pairs whose bounding boxes are at least that far apart cannot be under it:
  // skip their narrow phase (GJK, the dominant cost) and let the broadphase prune by the threshold.
  const bool skip = (search.stop_below > 0.0 && a->getAABB().distance(b->getAABB()) >= search.stop_below) ||
                    allowedContact(search, a, b);
  if (!skip && search.minimum > search.stop_below) {
    const std::size_t i = indexOf(search, a), j = indexOf(search, b);
    const bool ordered = i < j;
    PairMemo& memo = (*search.memos)[ordered ? i * search.object_count + j : j * search.object_count + i];
    const double moved = (*search.travelled)[i] + (*search.travelled)[j] - memo.travelled_first - memo.travelled_second;
    // An exact minimum skips a pair that cannot be closer than the smallest distance found so
    // far: neither object can have come closer than the distance it had at its last measurement
    // minus the distance both travelled since. Thresholded checks (the planner's) never do.
    const bool bounded = search.stop_below == 0.0 && memo.distance >= 0.0 &&
                         memo.distance - moved >= search.minimum + kMemoSlack;
    if (!bounded) {
      // Neither object moved since the pair was measured (travel is exactly 0 only for the same
      // transform): the same distance, without the narrow phase. Objects on a robot's fixed base
      // and the world's never move, and one robot often holds while the other moves.
      double d = memo.distance;
      if (!(memo.distance >= 0.0 && moved == 0.0)) {
        fcl::DistanceResultd result;
        fcl::distance(a, b, search.request, result);
        // FCL reports penetration as a negative value (-1 without signed distance): clamp to contact.
        d = std::max(0.0, result.min_distance);
        memo = {d, (*search.travelled)[ordered ? i : j], (*search.travelled)[ordered ? j : i]};
      }
      if (d < search.minimum) {
        search.minimum = d;
        search.first = a;
        search.second = b;
      }
    }
  }
  distance = search.stop_below > 0.0 ? std::min(search.minimum, search.stop_below) : search.minimum;
  return search.minimum <= search.stop_below;
}

/// Farthest any point of `geometry` is from its own frame's origin [m].
double reach(const fcl::CollisionGeometryd& geometry) { return geometry.aabb_center.norm() + geometry.aabb_radius; }

/// An upper bound of how far any point within `reach` m of the frame's origin moves from
/// `before` to `after` [m]: the origin's displacement plus reach times the rotation's largest
/// stretch ‖R_after − R_before‖₂ = 2 sin(θ/2) = √(3 − tr(R_beforeᵀ R_after)) (θ: the angle between
/// them). 0 for the same transform.
double travel(const fcl::Transform3d& before, const fcl::Transform3d& after, double reach) {
  if (before.matrix() == after.matrix()) return 0.0;
  const double trace = (before.linear().transpose() * after.linear()).trace();
  // Rounding may leave 3 − trace a little negative, or under the true value: the square root of
  // 1e-15 (3e-8) covers it for the sizes of a scene.
  const double stretch = std::sqrt(std::max(0.0, 3.0 - trace) + 1e-15);
  return (after.translation() - before.translation()).norm() + reach * stretch;
}

}  // namespace

struct CollisionWorld::Impl {
  struct Attached {
    std::size_t object = 0;
    std::size_t link = 0;
  };
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;  // scene order
  std::vector<fcl::Transform3d> offsets;                         // shape in attachment frame
  std::vector<std::unique_ptr<fcl::DynamicAABBTreeCollisionManagerd>> managers;  // per group
  std::vector<std::vector<Attached>> attached;                   // per robot
  std::vector<std::vector<std::size_t>> robot_groups;            // per robot: groups it moves
  std::vector<std::size_t> links_used;                           // per robot
  std::vector<std::pair<const void*, const void*>> allowed;      // allowed contacts (user data)
  std::vector<std::pair<std::size_t, std::size_t>> allowed_indices, primitive_indices;  // the same, object indices
  std::vector<std::pair<const void*, const void*>> primitive;    // primitive contacts (user data)
  /// Minimum distance over `pairs` of objects (scene indices) [m] (+infinity for none).
  double contactDistance(const std::vector<std::pair<std::size_t, std::size_t>>& pairs);
  /// Distance between objects `a` and `b` [m]: the pair's memo while neither moved since it was
  /// measured (the same transforms, the same distance), else measured and memoised.
  double pairDistance(std::size_t a, std::size_t b);
  // Per object: how far [m] it reaches from its frame's origin, and an upper bound of the path
  // length any of its points travelled since the world was made (never decreases).
  std::vector<double> reach;
  std::vector<double> travelled;
  std::vector<PairMemo> memos;  // per pair of objects, [lower index * objects + higher index]
};

CollisionWorld::CollisionWorld(SceneDescription scene) : scene_(std::move(scene)), impl_(std::make_unique<Impl>()) {
  scene_.validate();
  Impl& impl = *impl_;
  impl.managers.resize(scene_.groups.size());
  for (auto& manager : impl.managers) manager = std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>();
  impl.attached.resize(scene_.robots.size());
  impl.robot_groups.resize(scene_.robots.size());
  impl.links_used.assign(scene_.robots.size(), 0);
  for (std::size_t i = 0; i < scene_.objects.size(); ++i) {
    const ObjectDescription& description = scene_.objects[i];
    const std::size_t group = scene_.groupIndex(description.group);
    KDL::Frame pose = description.offset;
    if (!description.attached_to.isWorld()) {
      const std::size_t robot = scene_.robotIndex(description.attached_to.robot_name);
      impl.attached[robot].push_back({i, description.attached_to.link_index});
      auto& groups = impl.robot_groups[robot];
      if (std::find(groups.begin(), groups.end(), group) == groups.end()) groups.push_back(group);
      impl.links_used[robot] = std::max(impl.links_used[robot], description.attached_to.link_index + 1);
      pose = scene_.robots[robot].base_in_world * description.offset;
    }
    impl.offsets.push_back(toFcl(description.offset));
    auto object = std::make_unique<fcl::CollisionObjectd>(makeGeometry(description), toFcl(pose));
    object->computeAABB();
    object->setUserData(&scene_.objects[i]);
    impl.reach.push_back(reach(*object->collisionGeometry()));
    impl.managers[group]->registerObject(object.get());
    impl.objects.push_back(std::move(object));
  }
  for (auto& manager : impl.managers) {
    manager->setup();
    // From now on a moved robot's links are refitted in place (update()) and the tree is not
    // rebalanced: a group's tree holds a handful of objects, and FCL's default incremental passes
    // (leaves removed and reinserted after every move, for every validity check of a plan) cost
    // more than the traversal they could save. The distances do not depend on the tree's shape.
    manager->tree_incremental_balance_pass = 0;
    manager->max_tree_nonbalanced_level = std::numeric_limits<int>::max();
  }
  for (const auto& [contacts, indices, user] :
       {std::tuple{&scene_.allowed_contacts, &impl.allowed_indices, &impl.allowed},
        std::tuple{&scene_.primitive_contacts, &impl.primitive_indices, &impl.primitive}}) {
    for (const auto& [a, b] : *contacts) {
      indices->emplace_back(scene_.objectIndex(a), scene_.objectIndex(b));
      user->emplace_back(&scene_.objects[indices->back().first], &scene_.objects[indices->back().second]);
    }
  }
  impl.travelled.assign(scene_.objects.size(), 0.0);
  impl.memos.resize(scene_.objects.size() * scene_.objects.size());
}

CollisionWorld::~CollisionWorld() = default;

std::size_t CollisionWorld::linksUsedBy(std::size_t robot) const { return impl_->links_used.at(robot); }

void CollisionWorld::setRobotLinks(std::size_t robot, std::span<const KDL::Frame> links_in_world) {
  Impl& impl = *impl_;
  for (const Impl::Attached& attached : impl.attached[robot]) {
    fcl::CollisionObjectd& object = *impl.objects[attached.object];
    const fcl::Transform3d pose = toFcl(links_in_world[attached.link]) * impl.offsets[attached.object];
    impl.travelled[attached.object] += travel(object.getTransform(), pose, impl.reach[attached.object]);
    object.setTransform(pose);
    object.computeAABB();
  }
  for (const std::size_t group : impl.robot_groups[robot]) impl.managers[group]->update();
}

GroupDistance CollisionWorld::distance(std::size_t first, std::size_t second, double stop_below,
                                       bool primitive_contacts_apart) const {
  return query(first, second, stop_below, std::numeric_limits<double>::infinity(), primitive_contacts_apart);
}

GroupDistance CollisionWorld::distanceUnder(std::size_t first, std::size_t second, double bound,
                                            bool primitive_contacts_apart) const {
  return query(first, second, 0.0, bound, primitive_contacts_apart);
}

GroupDistance CollisionWorld::query(std::size_t first, std::size_t second, double stop_below, double bound,
                                    bool primitive_contacts_apart) const {
  DistanceSearch search;
  search.minimum = bound;
  search.objects = scene_.objects.data();
  search.object_count = scene_.objects.size();
  search.memos = &impl_->memos;
  search.travelled = &impl_->travelled;
  // FCL's own GJK instead of libccd's (FCL's default): the same distances, and no heap allocation
  // between primitives (libccd allocates its simplex per query), so a check on a primitive-only
  // scene allocates nothing (real_robots_test, bench/planning_bench.cpp).
  search.request.gjk_solver_type = fcl::GJKSolverType::GST_INDEP;
  search.stop_below = stop_below;
  search.allowed = &impl_->allowed;
  if (primitive_contacts_apart) search.primitive = &impl_->primitive;
  impl_->managers.at(first)->distance(impl_->managers.at(second).get(), &search, distanceCallback);
  GroupDistance result;
  result.distance = search.minimum;
  if (search.first != nullptr) {
    const auto* a = static_cast<const ObjectDescription*>(search.first->getUserData());
    const auto* b = static_cast<const ObjectDescription*>(search.second->getUserData());
    // The broadphase may hand the pair over in either order: report it in (first, second) order.
    if (a->group != scene_.groups[first]) std::swap(a, b);
    result.first_object = a->name;
    result.second_object = b->name;
    result.first_index = static_cast<std::size_t>(a - scene_.objects.data());
    result.second_index = static_cast<std::size_t>(b - scene_.objects.data());
  }
  return result;
}

double CollisionWorld::Impl::pairDistance(std::size_t a, std::size_t b) {
  const std::size_t lo = std::min(a, b), hi = std::max(a, b);
  PairMemo& memo = memos[lo * objects.size() + hi];
  if (memo.distance >= 0.0 && memo.travelled_first == travelled[lo] && memo.travelled_second == travelled[hi])
    return memo.distance;
  fcl::DistanceRequestd request;
  request.gjk_solver_type = fcl::GJKSolverType::GST_INDEP;
  fcl::DistanceResultd result;
  fcl::distance(objects[a].get(), objects[b].get(), request, result);
  const double d = std::max(0.0, result.min_distance);
  memo = {d, travelled[lo], travelled[hi]};
  return d;
}

double CollisionWorld::objectDistance(std::size_t a, std::size_t b) const {
  if (a >= impl_->objects.size() || b >= impl_->objects.size())
    throw std::out_of_range("CollisionWorld::objectDistance: object " + std::to_string(std::max(a, b)) +
                            " out of range (the scene has " + std::to_string(impl_->objects.size()) + ")");
  return impl_->pairDistance(a, b);
}

double CollisionWorld::Impl::contactDistance(const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  double minimum = std::numeric_limits<double>::infinity();
  for (const auto& [a, b] : pairs) minimum = std::min(minimum, pairDistance(a, b));
  return minimum;
}

double CollisionWorld::allowedContactDistance() const { return impl_->contactDistance(impl_->allowed_indices); }

double CollisionWorld::primitiveContactDistance() const { return impl_->contactDistance(impl_->primitive_indices); }

KDL::Frame CollisionWorld::objectPose(std::size_t object) const {
  return toKdl(impl_->objects.at(object)->getTransform());
}

}  // namespace cobra::planning
