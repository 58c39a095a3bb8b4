#include "core/backend/pose_graph.hpp"

#include <ceres/ceres.h>

#include <chrono>
#include <stdexcept>

namespace dammloam::backend {

namespace {

// Residual of a relative-pose measurement (t_ab, q_ab) between nodes a and b:
// [R_a^T (t_b - t_a) - t_ab ; 2 vec(q_ab^-1 q_a^-1 q_b)], whitened by sqrt information.
struct RelativePoseError {
  RelativePoseError(const Eigen::Vector3d& t, const Eigen::Quaterniond& q, const Matrix6d& sqrt_info)
      : t_ab(t), q_ab(q), sqrt_information(sqrt_info) {}

  template <typename T>
  bool operator()(const T* pa, const T* qa, const T* pb, const T* qb, T* out) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_a(pa), p_b(pb);
    Eigen::Map<const Eigen::Quaternion<T>> q_a(qa), q_b(qb);
    const Eigen::Quaternion<T> q_a_inv = q_a.conjugate();
    const Eigen::Quaternion<T> q_rel = q_a_inv * q_b;
    const Eigen::Matrix<T, 3, 1> p_rel = q_a_inv * (p_b - p_a);
    const Eigen::Quaternion<T> dq = q_ab.template cast<T>().conjugate() * q_rel;
    Eigen::Matrix<T, 6, 1> e;
    e.template head<3>() = p_rel - t_ab.template cast<T>();
    e.template tail<3>() = T(2.0) * dq.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> residual(out);
    residual = sqrt_information.template cast<T>() * e;
    return true;
  }

  Eigen::Vector3d t_ab;
  Eigen::Quaterniond q_ab;
  Matrix6d sqrt_information;
};

// Upper-triangular L^T with L L^T = information, after flooring the standard deviations.
Matrix6d SqrtInformation(Matrix6d covariance, double min_t_sigma, double min_r_sigma) {
  if (!covariance.allFinite()) covariance = Matrix6d::Identity();
  covariance = 0.5 * (covariance + covariance.transpose()).eval();
  for (int i = 0; i < 6; ++i) {
    const double floor = i < 3 ? min_t_sigma * min_t_sigma : min_r_sigma * min_r_sigma;
    covariance(i, i) = std::max(covariance(i, i), 0.0) + floor;
  }
  const Matrix6d information = covariance.inverse();
  Eigen::LLT<Matrix6d> llt(information);
  if (llt.info() != Eigen::Success) {
    Matrix6d diag = Matrix6d::Zero();
    for (int i = 0; i < 6; ++i) diag(i, i) = 1.0 / std::sqrt(covariance(i, i));
    return diag;
  }
  return llt.matrixU();
}

}  // namespace

std::uint32_t PoseGraph::AddNode(const Eigen::Isometry3d& T_world_node) {
  nodes_.push_back({});
  const auto id = static_cast<std::uint32_t>(nodes_.size() - 1);
  SetPose(id, T_world_node);
  return id;
}

void PoseGraph::SetPose(std::uint32_t id, const Eigen::Isometry3d& T_world_node) {
  Node& node = nodes_.at(id);
  Eigen::Map<Eigen::Vector3d>(node.position) = T_world_node.translation();
  Eigen::Map<Eigen::Quaterniond>(node.quaternion) =
      Eigen::Quaterniond(T_world_node.rotation()).normalized();
}

Eigen::Isometry3d PoseGraph::Pose(std::uint32_t id) const {
  const Node& node = nodes_.at(id);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Map<const Eigen::Quaterniond>(node.quaternion).normalized()
                   .toRotationMatrix();
  T.translation() = Eigen::Map<const Eigen::Vector3d>(node.position);
  return T;
}

void PoseGraph::AddEdge(std::uint32_t from, std::uint32_t to, const Eigen::Isometry3d& T_from_to,
                        const Matrix6d& covariance, bool loop) {
  if (from >= nodes_.size() || to >= nodes_.size() || from == to) {
    throw std::out_of_range("PoseGraph edge between unknown or identical nodes");
  }
  edges_.push_back({from, to, T_from_to.translation(),
                    Eigen::Quaterniond(T_from_to.rotation()).normalized(),
                    SqrtInformation(covariance, config_.min_translation_sigma,
                                    config_.min_rotation_sigma),
                    loop});
}

void PoseGraph::AddOdometryEdge(std::uint32_t from, std::uint32_t to,
                                const Eigen::Isometry3d& T_from_to, const Matrix6d& covariance) {
  AddEdge(from, to, T_from_to, covariance, false);
}

void PoseGraph::AddLoopEdge(std::uint32_t from, std::uint32_t to,
                            const Eigen::Isometry3d& T_from_to, const Matrix6d& covariance) {
  AddEdge(from, to, T_from_to, covariance, true);
}

void PoseGraph::RemoveLastEdge() {
  if (!edges_.empty()) edges_.pop_back();
}

std::size_t PoseGraph::NumLoopEdges() const {
  std::size_t n = 0;
  for (const Edge& e : edges_) n += e.loop ? 1 : 0;
  return n;
}

std::size_t PoseGraph::NumRejectedLoops() const {
  std::size_t n = 0;
  for (const Edge& e : edges_) n += (e.loop && !e.active) ? 1 : 0;
  return n;
}

double PoseGraph::WhitenedNorm(const Edge& e) const {
  const RelativePoseError error(e.t, e.q, e.sqrt_information);
  const Node& a = nodes_[e.from];
  const Node& b = nodes_[e.to];
  double residual[6];
  error(a.position, a.quaternion, b.position, b.quaternion, residual);
  return Eigen::Map<const Vector6d>(residual).norm();
}

double PoseGraph::LastEdgeResidual() const {
  return edges_.empty() ? 0.0 : WhitenedNorm(edges_.back());
}

std::vector<double> PoseGraph::LoopResiduals() const {
  std::vector<double> out;
  for (const Edge& e : edges_) {
    if (e.loop) out.push_back(WhitenedNorm(e));
  }
  return out;
}

void PoseGraph::Solve(PoseGraphSummary& summary) {
  ceres::Problem problem;
  for (Node& node : nodes_) {
    problem.AddParameterBlock(node.position, 3);
    problem.AddParameterBlock(node.quaternion, 4, new ceres::EigenQuaternionManifold);
  }
  for (const Edge& e : edges_) {
    if (!e.active) continue;
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4>(
        new RelativePoseError(e.t, e.q, e.sqrt_information));
    ceres::LossFunction* loss = e.loop ? new ceres::HuberLoss(config_.loop_huber_scale) : nullptr;
    Node& a = nodes_[e.from];
    Node& b = nodes_[e.to];
    problem.AddResidualBlock(cost, loss, a.position, a.quaternion, b.position, b.quaternion);
  }
  problem.SetParameterBlockConstant(nodes_[0].position);
  problem.SetParameterBlockConstant(nodes_[0].quaternion);

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = config_.max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary ceres_summary;
  ceres::Solve(options, &problem, &ceres_summary);
  if (summary.iterations == 0) summary.initial_cost = ceres_summary.initial_cost;
  summary.final_cost = ceres_summary.final_cost;
  summary.iterations += static_cast<int>(ceres_summary.iterations.size());
  summary.converged = ceres_summary.termination_type == ceres::CONVERGENCE;
}

PoseGraphSummary PoseGraph::Optimize() {
  PoseGraphSummary summary;
  if (nodes_.size() < 2 || edges_.empty()) {
    summary.converged = true;
    return summary;
  }
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Node> initial = nodes_;
  while (true) {
    nodes_ = initial;
    Solve(summary);
    // Switch off the worst inconsistent loop, if any, and start again without it.
    Edge* worst = nullptr;
    double worst_norm = config_.loop_prune_threshold;
    for (Edge& e : edges_) {
      if (!e.loop || !e.active) continue;
      const double norm = WhitenedNorm(e);
      if (norm > worst_norm) {
        worst_norm = norm;
        worst = &e;
      }
    }
    if (worst == nullptr || summary.rejected_loops >= config_.max_prune_rounds) break;
    worst->active = false;
    ++summary.rejected_loops;
  }
  summary.solve_ms = std::chrono::duration<double, std::milli>(
                         std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace dammloam::backend
