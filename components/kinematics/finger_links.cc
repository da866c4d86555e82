#include "components/kinematics/finger_links.h"

#include <algorithm>
#include <cmath>

#include "components/runtime/check.h"

namespace dmpl {

namespace {

// Points 0 .. n - 1 spread over [-half, half], at most kLinkPointSpacingM apart (n >= 2).
std::vector<double> Spread(double half) {
  const int n = std::max(2, static_cast<int>(std::ceil(2 * half / kLinkPointSpacingM)) + 1);
  std::vector<double> out(n);
  for (int i = 0; i < n; ++i) out[i] = -half + 2 * half * i / (n - 1);
  return out;
}

}  // namespace

LinkSolid SolidOf(const CollisionShape& shape) {
  LinkSolid s;
  std::vector<Eigen::Vector3d> local;
  switch (shape.kind) {
    case CollisionShape::Kind::kSphere:
      s.radius = shape.radius;
      local.push_back(Eigen::Vector3d::Zero());
      break;
    case CollisionShape::Kind::kCylinder: {
      // The two end discs (rings and centres) and rings along the mantle.
      const int around = std::max(8, static_cast<int>(std::ceil(2 * M_PI * shape.radius /
                                                                kLinkPointSpacingM)));
      for (const double z : Spread(shape.length / 2)) {
        for (int k = 0; k < around; ++k) {
          const double a = 2 * M_PI * k / around;
          local.emplace_back(shape.radius * std::cos(a), shape.radius * std::sin(a), z);
        }
      }
      for (const double z : {-shape.length / 2, shape.length / 2}) {
        for (const double r : Spread(shape.radius)) {
          if (r == 0.0) continue;  // the centre, below
          local.emplace_back(r, 0.0, z);
          local.emplace_back(0.0, r, z);
        }
        local.emplace_back(0.0, 0.0, z);
      }
      break;
    }
    case CollisionShape::Kind::kBox: {
      // A grid over the box whose points on its faces are kept.
      const std::vector<double> xs = Spread(shape.box_size.x() / 2),
                                ys = Spread(shape.box_size.y() / 2),
                                zs = Spread(shape.box_size.z() / 2);
      for (size_t i = 0; i < xs.size(); ++i) {
        for (size_t j = 0; j < ys.size(); ++j) {
          for (size_t k = 0; k < zs.size(); ++k) {
            const bool face = i == 0 || i + 1 == xs.size() || j == 0 || j + 1 == ys.size() ||
                              k == 0 || k + 1 == zs.size();
            if (face) local.emplace_back(xs[i], ys[j], zs[k]);
          }
        }
      }
      break;
    }
  }
  for (const Eigen::Vector3d& p : local) s.points.push_back(shape.origin * p);
  return s;
}

FingerLinks::FingerLinks(const HandModel& model, const FingerKinematics& finger)
    : finger_(finger) {
  for (int k = 0; k < finger.num_links(); ++k) {
    const int link = model.FindLink(finger.LinkName(k));
    DMPL_DEMAND(link >= 0);
    for (const CollisionShape& shape : model.links()[link].collisions) {
      LinkSolid s = SolidOf(shape);
      s.link = finger.LinkName(k);
      s.tip = k == finger.num_links() - 1;
      chain_link_.push_back(k);
      local_.push_back(std::move(s));
    }
  }
}

std::vector<LinkSolid> FingerLinks::Solids(const Eigen::VectorXd& q) const {
  std::vector<Eigen::Isometry3d> frames;
  finger_.LinkFrames(q, &frames);
  std::vector<LinkSolid> out = local_;
  for (size_t i = 0; i < out.size(); ++i) {
    for (Eigen::Vector3d& p : out[i].points) p = frames[chain_link_[i]] * p;
  }
  return out;
}

}  // namespace dmpl
