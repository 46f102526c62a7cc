// Compiled search of robotica_kin.ik (numerical inverse kinematics, book §4.4).
//
// robotica_kin/ik.py validates the input and documents the method; this file runs the search
// of one call: for each goal pose, starts in order (q0, then the seed table nearest first, then
// random configurations), from each a damped least-squares iteration
//
//     (J^T J + lambda I) dq = J^T e,   lambda = e^T e / 2
//
// (plain Newton steps close to the goal for a square Jacobian), and the 2π fitting of revolute
// angles into the joint limits. Kinematics are Pinocchio's (forward kinematics, Jacobians, log6
// / log3); the model is the one robotica_kin.pinocchio_model builds, serialised by Pinocchio in
// Python and read here. The interface is plain C for ctypes.

#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/multibody.hpp>
#include <pinocchio/serialization.hpp>
#include <pinocchio/spatial.hpp>

#include "c_error.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace
{

using pinocchio::Data;
using pinocchio::Model;
using pinocchio::SE3;
using Matrix6x = Eigen::Matrix<double, 6, Eigen::Dynamic>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

constexpr double kTwoPi = 2.0 * M_PI;
constexpr double kNewtonErrorSq = 1e-2;  // [m^2, rad^2] below this squared error: Newton steps
constexpr int kFeatures = 12;            // seed feature: [p, sqrt(w) R(:)] of frame {n}
constexpr long kSortChunk = 16;          // seeds put in order at a time

struct Search
{
  Eigen::VectorXd q;
  long iterations;
  double residual;  // infinity when the search did not converge
};

// One robot and one seed table: what does not change between calls.
class Robot
{
public:
  Robot(const std::string & model_text, const std::string & tool_frame,
    const unsigned char * revolute, long seed_count, const double * seed_q,
    const double * seed_features, double rotation_scale)
  : rotation_scale_(rotation_scale)
  {
    model_.loadFromString(model_text);
    if (!model_.existFrame(tool_frame)) {
      throw std::runtime_error("the model has no frame " + tool_frame);
    }
    const auto & frame = model_.frames[model_.getFrameId(tool_frame)];
    tool_frame_ = model_.getFrameId(tool_frame);
    last_joint_ = frame.parentJoint;
    tool_ = frame.placement;
    has_tool_ = !tool_.isIdentity(0.0);
    tool_inverse_ = tool_.inverse();
    n_ = model_.nq;
    revolute_.assign(revolute, revolute + n_);
    lower_ = model_.lowerPositionLimit;
    upper_ = model_.upperPositionLimit;
    seed_q_ = Eigen::Map<const Eigen::MatrixXd>(seed_q, n_, seed_count);  // column per seed
    features_ = Eigen::Map<const Eigen::MatrixXd>(seed_features, kFeatures, seed_count);
    features_sq_ = features_.colwise().squaredNorm().transpose();
    positions_sq_ = features_.topRows<3>().colwise().squaredNorm().transpose();
  }

  int n() const {return n_;}

  std::unique_ptr<Data> acquire_data()
  {
    std::lock_guard<std::mutex> lock(pool_mutex_);
    if (pool_.empty()) {
      return std::make_unique<Data>(model_);
    }
    auto data = std::move(pool_.back());
    pool_.pop_back();
    return data;
  }

  void release_data(std::unique_ptr<Data> data)
  {
    std::lock_guard<std::mutex> lock(pool_mutex_);
    pool_.push_back(std::move(data));
  }

  friend class Solver;

private:
  Model model_;
  pinocchio::FrameIndex tool_frame_ = 0;
  pinocchio::JointIndex last_joint_ = 0;
  SE3 tool_ = SE3::Identity();
  SE3 tool_inverse_ = SE3::Identity();
  bool has_tool_ = false;
  int n_ = 0;
  std::vector<unsigned char> revolute_;
  Eigen::VectorXd lower_, upper_;
  Eigen::MatrixXd seed_q_, features_;
  double rotation_scale_;  // [m] weight of the rotation entries in the features
  Eigen::VectorXd features_sq_, positions_sq_;
  std::mutex pool_mutex_;
  std::vector<std::unique_ptr<Data>> pool_;
};

// The search of one call (one mask, tolerance and limits) on one robot.
class Solver
{
public:
  Solver(Robot & robot, Data & data, const double * mask, double stol, long slimit,
    std::uint64_t seed)
  : r_(robot), data_(data), stol_(stol), slimit_(slimit), seed_(seed), J_(6, robot.n_),
    Jw_(6, robot.n_)
  {
    if (mask != nullptr) {
      for (int i = 0; i < 6; ++i) {
        if (mask[i] != 0.0) {
          rows_.push_back(i);
        }
      }
    }
    masked_ = mask != nullptr;
    newton_ = !masked_ && r_.n_ == 6;
  }

  // Solve for one goal pose of the tool (row-major 4x4); write [q, residual, iterations,
  // success] to out and return success.
  bool solve(const double * pose, const Eigen::VectorXd * q0, long ilimit, double * out)
  {
    Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> T(pose);
    const SE3 goal(T.topLeftCorner<3, 3>(), T.topRightCorner<3, 1>());
    const SE3 goal_n = r_.has_tool_ ? goal * r_.tool_inverse_ : goal;
    long iterations = 0;
    Eigen::VectorXd q;
    Eigen::VectorXd distance;  // of each seed to the goal, computed for the first seed
    long nearest = 0;
    std::vector<long> order;   // the other seeds; order[0, sorted) nearest first
    long sorted = 0;
    std::unique_ptr<std::mt19937_64> rng;
    // ilimit >= 1, so at least one search runs.
    for (long start = q0 == nullptr ? 1 : 0; iterations < ilimit; ++start) {
      Eigen::VectorXd q_start;
      const long seeds = r_.seed_q_.cols();
      if (start == 0) {
        q_start = *q0;
      } else if (start == 1) {
        distance = seed_distance(goal_n);
        distance.minCoeff(&nearest);
        q_start = r_.seed_q_.col(nearest);
      } else if (start <= seeds) {
        const long i = start - 2;
        if (order.empty()) {
          order.reserve(seeds - 1);
          for (long j = 0; j < seeds; ++j) {
            if (j != nearest) {
              order.push_back(j);
            }
          }
        }
        if (i >= sorted) {  // sort the next few only: most searches need one or two seeds
          const long next = std::min(sorted + kSortChunk, static_cast<long>(order.size()));
          std::partial_sort(order.begin() + sorted, order.begin() + next, order.end(),
            [&distance](long a, long b) {return distance[a] < distance[b];});
          sorted = next;
        }
        q_start = r_.seed_q_.col(order[i]);
      } else {
        if (!rng) {
          rng = std::make_unique<std::mt19937_64>(seed_);
        }
        q_start.resize(r_.n_);
        for (int i = 0; i < r_.n_; ++i) {
          // 53 random bits give a uniform double in [0, 1), independent of the C++ library.
          const double u = static_cast<double>((*rng)() >> 11) * 0x1.0p-53;
          q_start[i] = r_.lower_[i] + u * (r_.upper_[i] - r_.lower_[i]);
        }
      }
      const long limit = std::min(slimit_, ilimit - iterations);
      Search s = masked_ ? search_world(q_start, goal, limit) : search_local(q_start, goal,
        goal_n, limit);
      iterations += s.iterations;
      q = std::move(s.q);
      if (s.residual < stol_ && fit_limits(q)) {
        return report(q, s.residual, iterations, true, out);
      }
    }
    return report(q, std::sqrt(world_error(q, goal).squaredNorm()), iterations, false, out);
  }



private:
  bool report(const Eigen::VectorXd & q, double residual, long iterations, bool success,
    double * out) const
  {
    Eigen::Map<Eigen::VectorXd>(out, r_.n_) = q;
    out[r_.n_] = residual;
    out[r_.n_ + 1] = static_cast<double>(iterations);
    out[r_.n_ + 2] = success ? 1.0 : 0.0;
    return success;
  }

  // Squared distance (up to a constant) of each seed's feature to the goal's; positions only
  // with a mask (it leaves some orientation free).
  Eigen::VectorXd seed_distance(const SE3 & goal_n) const
  {
    if (masked_) {
      return r_.positions_sq_ - 2.0 * r_.features_.topRows<3>().transpose() *
             goal_n.translation();
    }
    Eigen::Matrix<double, kFeatures, 1> feature;
    feature.head<3>() = goal_n.translation();
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> R = goal_n.rotation();
    feature.tail<9>() = r_.rotation_scale_ *
      Eigen::Map<const Eigen::Matrix<double, 9, 1>>(R.data());
    return r_.features_sq_ - 2.0 * r_.features_.transpose() * feature;
  }

  // [p_d - p; log(R_d R^T)] of a tool pose, in {0}.
  static Vector6 pose_error(const SE3 & pose, const SE3 & goal)
  {
    Vector6 e;
    e.head<3>() = goal.translation() - pose.translation();
    e.tail<3>() = pinocchio::log3(goal.rotation() * pose.rotation().transpose());
    return e;
  }

  // Masked base-frame pose error at q; leaves the tool Jacobian (LOCAL_WORLD_ALIGNED) in Jw_.
  Eigen::VectorXd world_error(const Eigen::VectorXd & q, const SE3 & goal, bool jacobian = false)
  {
    if (jacobian) {
      pinocchio::computeJointJacobians(r_.model_, data_, q);
    } else {
      pinocchio::forwardKinematics(r_.model_, data_, q);
    }
    pinocchio::updateFramePlacement(r_.model_, data_, r_.tool_frame_);
    if (jacobian) {
      Jw_.setZero();
      pinocchio::getFrameJacobian(r_.model_, data_, r_.tool_frame_,
        pinocchio::LOCAL_WORLD_ALIGNED, Jw_);
    }
    const Vector6 e = pose_error(data_.oMf[r_.tool_frame_], goal);
    if (!masked_) {
      return e;
    }
    Eigen::VectorXd masked(rows_.size());
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      masked[i] = e[rows_[i]];
    }
    return masked;
  }

  // Damped least-squares step (J^T J + err_sq / 2 I) dq = J^T e; false if not positive definite.
  template<typename JacobianType, typename ErrorType>
  bool damped_step(const JacobianType & J, const ErrorType & e, double err_sq,
    Eigen::VectorXd & q)
  {
    Eigen::MatrixXd A = J.transpose() * J;
    A.diagonal().array() += 0.5 * err_sq;
    Eigen::LLT<Eigen::MatrixXd> llt(A);
    if (llt.info() != Eigen::Success) {
      return false;
    }
    q += llt.solve(J.transpose() * e);
    return true;
  }

  // Iterate without a mask: error log6(T_n^-1 T_goal_n) in {n}, Jacobian of joint n in {n}.
  Search search_local(Eigen::VectorXd q, const SE3 & goal, const SE3 & goal_n, long limit)
  {
    const double tol_sq = stol_ * stol_;
    for (long k = 0; k <= limit; ++k) {
      J_.setZero();
      pinocchio::computeJointJacobian(r_.model_, data_, q, r_.last_joint_, J_);
      const SE3 & pose_n = data_.iMf[0];  // left there by computeJointJacobian
      const Vector6 e = pinocchio::log6(pose_n.actInv(goal_n)).toVector();
      const double err_sq = e.squaredNorm();
      if (err_sq < tol_sq) {
        const SE3 pose = r_.has_tool_ ? SE3(pose_n * r_.tool_) : pose_n;
        const double residual = std::sqrt(pose_error(pose, goal).squaredNorm());
        if (residual < stol_) {
          return {q, k, residual};
        }
      }
      if (k == limit) {
        break;
      }
      if (newton_ && err_sq < kNewtonErrorSq) {
        const Eigen::Matrix<double, 6, 6> Js = J_;
        Eigen::PartialPivLU<Eigen::Matrix<double, 6, 6>> lu(Js);
        if ((lu.matrixLU().diagonal().array() != 0.0).all()) {
          q += lu.solve(e);
          continue;
        }
      }
      if (!damped_step(J_, e, err_sq, q)) {
        break;
      }
    }
    return {q, limit, std::numeric_limits<double>::infinity()};
  }

  // Iterate with a mask: base-frame error and the matching rows of the tool Jacobian.
  Search search_world(Eigen::VectorXd q, const SE3 & goal, long limit)
  {
    const double tol_sq = stol_ * stol_;
    Eigen::MatrixXd J(rows_.size(), r_.n_);
    for (long k = 0; k <= limit; ++k) {
      const Eigen::VectorXd e = world_error(q, goal, true);
      const double err_sq = e.squaredNorm();
      if (err_sq < tol_sq) {
        return {q, k, std::sqrt(err_sq)};
      }
      if (k == limit) {
        break;
      }
      for (std::size_t i = 0; i < rows_.size(); ++i) {
        J.row(i) = Jw_.row(rows_[i]);
      }
      if (!damped_step(J, e, err_sq, q)) {
        break;
      }
    }
    return {q, limit, std::numeric_limits<double>::infinity()};
  }

  // Shift revolute angles by multiples of 2π into the limits; false if impossible.
  bool fit_limits(Eigen::VectorXd & q) const
  {
    auto within = [this](const Eigen::VectorXd & x) {
        return (x.array() >= r_.lower_.array()).all() && (x.array() <= r_.upper_.array()).all();
      };
    if (within(q)) {
      return true;
    }
    Eigen::VectorXd shifted = q;
    for (int i = 0; i < r_.n_; ++i) {
      if (!r_.revolute_[i]) {
        continue;
      }
      double x = shifted[i] - kTwoPi * std::nearbyint(shifted[i] / kTwoPi);
      if (x < r_.lower_[i]) {
        x += kTwoPi;
      } else if (x > r_.upper_[i]) {
        x -= kTwoPi;
      }
      shifted[i] = x;
    }
    if (!within(shifted)) {
      return false;
    }
    q = shifted;
    return true;
  }

  Robot & r_;
  Data & data_;
  double stol_;
  long slimit_;
  std::uint64_t seed_;
  std::vector<int> rows_;
  bool masked_ = false;
  bool newton_ = false;
  Matrix6x J_, Jw_;
};

// True if a row-major 4x4 pose is finite, its rotation block orthonormal (1e-6) with det +1
// and its last row [0 0 0 1] (1e-9).
bool is_homogeneous(const double * pose)
{
  Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> T(pose);
  if (!T.allFinite()) {
    return false;
  }
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const Eigen::RowVector4d last(0.0, 0.0, 0.0, 1.0);
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-6 &&
         R.determinant() > 0.0 && (T.row(3) - last).cwiseAbs().maxCoeff() <= 1e-9;
}

}  // namespace

extern "C" {

// Read a Pinocchio model (Model::saveToString), its tool frame's name, which joints are revolute
// (n flags) and a seed table: seed_q (seed_count x n) and seed_features (seed_count x 12, each
// [p, rotation_scale R(:)] of frame {n}, R row-major), row-major. Return a handle, or NULL with
// a message in error.
__attribute__((visibility("default")))
void * rik_robot_new(const char * model_text, const char * tool_frame,
  const unsigned char * revolute, long seed_count, const double * seed_q,
  const double * seed_features, double rotation_scale, char * error, long error_size)
{
  return new_or_report([&] {
      return new Robot(model_text, tool_frame, revolute, seed_count, seed_q, seed_features,
               rotation_scale);
    }, error, error_size);
}

__attribute__((visibility("default")))
void rik_robot_free(void * robot)
{
  delete static_cast<Robot *>(robot);
}

// Solve m goal poses (row-major 4x4 each) of the tool, each point starting from q0 (may be
// NULL) and then from the previous point's solution when that one succeeded. mask: six 0/1
// weights of [x y z rx ry rz] in {0}, NULL for all six (the error is then measured in {n}).
// out: m rows of n + 3 values [q, residual, iterations, success (0/1)].
// Return 0; k + 1 (nothing solved) if pose k is not a homogeneous transform; -1 with a message
// in error on a C++ exception.
__attribute__((visibility("default")))
long rik_solve(void * robot, long m, const double * poses, const double * q0,
  const double * mask, double stol, long ilimit, long slimit, std::uint64_t seed, double * out,
  char * error, long error_size)
{
  for (long k = 0; k < m; ++k) {
    if (!is_homogeneous(poses + 16 * k)) {
      return k + 1;
    }
  }
  auto & r = *static_cast<Robot *>(robot);
  std::unique_ptr<Data> data;
  try {
    data = r.acquire_data();
    Solver solver(r, *data, mask, stol, slimit, seed);
    const int n = r.n();
    Eigen::VectorXd start;
    bool has_start = q0 != nullptr;
    if (has_start) {
      start = Eigen::Map<const Eigen::VectorXd>(q0, n);
    }
    for (long k = 0; k < m; ++k) {
      double * row = out + (n + 3) * k;
      if (solver.solve(poses + 16 * k, has_start ? &start : nullptr, ilimit, row)) {
        start = Eigen::Map<const Eigen::VectorXd>(row, n);
        has_start = true;
      }
    }
  } catch (const std::exception & e) {
    copy_message(e.what(), error, error_size);
    if (data) {
      r.release_data(std::move(data));
    }
    return -1;
  }
  r.release_data(std::move(data));
  return 0;
}

}  // extern "C"
