#include "scene_graph_tracker/registration/ray_correspondences.hpp"

#include <tbb/parallel_reduce.h>

#include "scene_graph_tracker/geometry/rigid.hpp"
#include "scene_graph_tracker/registration/tile_order.hpp"

namespace sgt {

void NodeGroups::set(NodeId node, int group) {
  if (node < 0) return;
  if (static_cast<std::size_t>(node) >= group_.size()) group_.resize(node + 1, -1);
  group_[node] = group;
  groups_ = std::max(groups_, group + 1);
}

std::vector<std::vector<RayPair>> collectRayPairs(const RaycastScene& scene,
                                                  const RangeMeasurements& m, const TileSet& tiles,
                                                  const NodeGroups& groups,
                                                  const RangeTolerance& max_dist, RayHits& hits,
                                                  PairingStats* stats) {
  const int n_groups = groups.groupCount();
  std::vector<std::vector<RayPair>> out(n_groups);
  if (stats) stats->expected.assign(n_groups, 0);
  if (tiles.tiles().empty() || n_groups == 0) return out;
  // A surface beyond the measurement plus the threshold cannot pair with it: rays stop there.
  scene.cast(*m.rays, m.T_world_sensor, hits, &tiles, CastLimit{&m.range, max_dist});

  const Eigen::Matrix3f R = m.T_world_sensor.linear().cast<float>();
  const Eigen::Vector3f o = m.T_world_sensor.translation().cast<float>();
  const SensorRays& rays = *m.rays;
  const RangeTolerance* within = stats ? stats->expected_within : nullptr;
  std::vector<int> expected(n_groups, 0);
  collectInTileOrder(
      tiles.tiles().size(), out, &expected, [&](std::size_t b, auto& pairs, int* count) {
        tiles.forTile(rays, b, [&](int, std::size_t i) {
          const int g = groups(hits.node[i]);
          if (g < 0 || !m.valid(i)) return;
          if (!within || hits.range[i] <= m.range[i] + within->at(m.range[i])) ++count[g];
          if (std::abs(hits.range[i] - m.range[i]) >= max_dist.at(m.range[i])) return;
          const Eigen::Vector3f origin =
              rays.origins.empty() ? o : Eigen::Vector3f(o + R * rays.origins[i]);
          pairs[g].push_back({origin + R * (rays.directions[i] * m.range[i]), hits.point[i],
                              hits.normal[i], static_cast<std::uint32_t>(i)});
        });
      });
  if (stats) stats->expected = std::move(expected);
  return out;
}

namespace {

// The prior's term for a step x = [w, dt] applied on the left of the running estimate (R, t):
// residual [log(R R_prior^T) + w, t - t_prior + w x t + dt], linearised.
void addPriorTerm(const AlignmentPrior& prior, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                  Eigen::Matrix<double, 6, 6>& H, Eigen::Matrix<double, 6, 1>& g) {
  const Eigen::AngleAxisd turn(R * prior.T.linear().transpose());
  Eigen::Matrix<double, 6, 1> r;
  r << turn.angle() * turn.axis(), t - prior.T.translation();
  Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Identity();
  J.bottomLeftCorner<3, 3>() << 0.0, t.z(), -t.y(), -t.z(), 0.0, t.x(), t.y(), -t.x(),
      0.0;  // -[t]x
  H.noalias() += J.transpose() * prior.information * J;
  g.noalias() += J.transpose() * prior.information * r;
}

// One point-to-plane least-squares step: residual n.(p - q), Jacobian [q x n, n] when the normal
// turns with the moving side, [p x n, n] when it belongs to the fixed side. The normal equations
// are summed in float over chunks of 1024 pairs (in parallel for large sets) and the chunks in
// double; each pair's row is weighted by `weights` when given, and `prior` adds its term.
bool linearPointToPlaneStep(const std::vector<Eigen::Vector3f>& moving,
                            const std::vector<Eigen::Vector3f>& fixed,
                            const std::vector<Eigen::Vector3f>& normals,
                            const std::vector<float>* weights, NormalSide side,
                            const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                            const std::array<bool, 6>& free, const AlignmentPrior* prior,
                            Eigen::Matrix3d& dR, Eigen::Vector3d& dt) {
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  struct Sums {
    Mat6 H = Mat6::Zero();
    Vec6 g = Vec6::Zero();
  };
  constexpr std::size_t kChunk = 1024;
  const auto chunk = [&](std::size_t begin, std::size_t end, Sums& out) {
    Eigen::Matrix<float, 6, 6> H = Eigen::Matrix<float, 6, 6>::Zero();
    Eigen::Matrix<float, 6, 1> g = Eigen::Matrix<float, 6, 1>::Zero();
    for (std::size_t i = begin; i < end; ++i) {
      const Eigen::Vector3f p = R * moving[i] + t;
      const Eigen::Vector3f n =
          side == NormalSide::kMoving ? Eigen::Vector3f(R * normals[i]) : normals[i];
      const Eigen::Vector3f& lever = side == NormalSide::kMoving ? fixed[i] : p;
      Eigen::Matrix<float, 6, 1> J;
      J << lever.cross(n), n;
      const float w = weights ? (*weights)[i] : 1.0f;
      H.noalias() += w * J * J.transpose();
      g.noalias() += (w * n.dot(p - fixed[i])) * J;
    }
    out.H += H.cast<double>();
    out.g += g.cast<double>();
  };
  const std::size_t n = moving.size();
  // Split and combined the same way in every run (simple partitioner), so the sums repeat exactly.
  const Sums sums = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, n, kChunk), Sums{},
      [&](const tbb::blocked_range<std::size_t>& r, Sums acc) {
        for (std::size_t b = r.begin(); b < r.end(); b += kChunk)
          chunk(b, std::min(r.end(), b + kChunk), acc);
        return acc;
      },
      [](Sums a, const Sums& b) {
        a.H += b.H, a.g += b.g;
        return a;
      });
  Mat6 H = sums.H;
  Vec6 g = sums.g;
  if (prior) addPriorTerm(*prior, R.cast<double>(), t.cast<double>(), H, g);
  H.diagonal().array() += 1e-9 + 1e-6 * H.trace() / 6.0;  // keeps unobservable directions still
  for (int i = 0; i < 6; ++i)
    if (!free[i]) H.row(i).setZero(), H.col(i).setZero(), H(i, i) = 1.0, g(i) = 0.0;  // held fixed
  const Vec6 x = H.ldlt().solve(-g);
  if (!x.allFinite()) return false;
  const Eigen::Vector3d w = x.head<3>();
  dR = w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix()
                    : Eigen::Matrix3d::Identity();
  dt = x.tail<3>();
  return true;
}

}  // namespace

IterativeAlignment alignPairs(const std::vector<Eigen::Vector3f>& moving,
                              const std::vector<Eigen::Vector3f>& fixed,
                              const std::vector<Eigen::Vector3f>& normals, NormalSide side,
                              StepSolver solver, int steps, double tolerance,
                              const AlignmentOptions& options, const std::vector<float>* weights,
                              const AlignmentPrior* prior) {
  IterativeAlignment out;
  const std::size_t n = moving.size();
  Eigen::Matrix3f R = Eigen::Matrix3f::Identity();
  Eigen::Vector3f t = Eigen::Vector3f::Zero();
  for (int s = 0; s < steps; ++s) {
    // Umeyama solvers need the moments of every step; the linear step only their first-step
    // degeneracy check (the spread of a rigidly moved set does not change).
    const bool need_moments = solver != StepSolver::kLinearPointToPlane || s == 0;
    Alignment step;
    if (need_moments) {
      PairMoments mom;
      for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3f p = R * moving[i] + t;
        const Eigen::Vector3f& q = fixed[i];
        Eigen::Vector3f a = p, b = q;
        if (solver == StepSolver::kUmeyamaPointToPlane) {
          if (side == NormalSide::kMoving) {
            const Eigen::Vector3f nn = R * normals[i];
            a = q + nn * nn.dot(p - q);  // foot of q on the moving tangent plane
          } else {
            const Eigen::Vector3f& nn = normals[i];
            b = p + nn * nn.dot(q - p);  // foot of p on the fixed tangent plane
          }
        }
        mom.add(a.cast<double>(), b.cast<double>());
      }
      out.last = mom;
      step = umeyama(mom, options);  // also the degeneracy check for every solver
      out.status = step.status;
      if (!step.ok()) break;
    }
    Eigen::Matrix3d dRd = step.T.linear();
    Eigen::Vector3d dtd = step.T.translation();
    if (solver == StepSolver::kLinearPointToPlane &&
        !linearPointToPlaneStep(moving, fixed, normals, weights, side, R, t, options.free_dofs,
                                prior, dRd, dtd))
      break;
    const Eigen::Matrix3f dR = dRd.cast<float>();
    const Eigen::Vector3f dt = dtd.cast<float>();
    R = dR * R;
    t = dR * t + dt;
    out.steps = s + 1;
    const double moved = dt.norm() + Eigen::AngleAxisf(dR).angle() * 0.1;  // 0.1 m lever
    if (moved < tolerance) break;
  }
  out.T.linear() = R.cast<double>();
  out.T.translation() = t.cast<double>();
  out.T = rigid(out.T);  // re-orthonormalise the float accumulation
  return out;
}

}  // namespace sgt
