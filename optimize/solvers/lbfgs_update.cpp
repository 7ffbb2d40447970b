#include "optimize/solvers/lbfgs_update.h"

#include <vector>

namespace flexure::optimize {

bool LbfgsPairs::add(const Eigen::VectorXd& s, const Eigen::VectorXd& t) {
  if (capacity_ <= 0) return false;
  const double curvature = s.dot(t);
  if (!(curvature > 1e-8 * s.norm() * t.norm())) return false;
  if (static_cast<int>(pairs_.size()) == capacity_) pairs_.pop_front();
  pairs_.push_back({s, t, 1.0 / curvature});
  return true;
}

Eigen::VectorXd LbfgsPairs::apply(
    const Eigen::VectorXd& q,
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& initial) const {
  std::vector<double> a(pairs_.size());
  Eigen::VectorXd r = q;
  for (int i = static_cast<int>(pairs_.size()) - 1; i >= 0; --i) {
    a[i] = pairs_[i].rho * pairs_[i].s.dot(r);
    r -= a[i] * pairs_[i].t;
  }
  r = initial(r);
  for (int i = 0; i < static_cast<int>(pairs_.size()); ++i) {
    const double b = pairs_[i].rho * pairs_[i].t.dot(r);
    r += (a[i] - b) * pairs_[i].s;
  }
  return r;
}

}  // namespace flexure::optimize
