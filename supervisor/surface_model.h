#pragma once
// What the hand has learned of the object's surface by touch: every fingertip contact, kept in
// the object's frame (from the object pose estimate at the moment of contact), with its normal
// (from the tip's geometry: contact_sensing.h) and its time. It answers "where is the surface,
// with what normal, in this direction from the centre", with how sure it is.
//
// The model is a set of local tangent planes: each contact says that near it the surface is
// the plane through its point with its normal. Along a direction d from the centre, each
// plane is met at t = (n . p) / (n . d); the estimate is those distances averaged with weights
// that fall off with the angle between d and the contact's own direction (a von Mises-Fisher
// kernel of width kernel_rad), and the normal likewise. On a face this is exact; on a curved
// surface it is right to first order where a sphere-about-the-centre model is not; the pose
// estimate's noise (0.5 cm in the paper) averages out over the contacts near d.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

namespace dmpl {

struct SurfaceModelParams {
  double kernel_rad = 0.3;        // angular width of a contact's say about nearby directions
  double min_support = 2.0;       // weight below which a direction counts as unexplored
  double min_spacing_m = 0.002;   // a contact closer than this to a kept one replaces it
  size_t max_contacts = 4000;     // the oldest go first
  double pose_sigma_m = 0.005;    // the object pose estimate's noise (for the uncertainty)
};

struct SurfacePoint {
  bool known = false;             // enough contacts near the direction (min_support)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // object frame
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, outward (object frame)
  double distance_m = 0.0;        // from the centre along the direction
  double sigma_m = 0.0;           // its uncertainty (spread of the planes and the pose noise)
  double support = 0.0;           // the kernel weight of the contacts behind it

  // Whether the surface is known to lie elsewhere than `distance` (m from the centre along the
  // same direction) by more than the model is sure of (twice its sigma, and at least 3 mm): where
  // it is not, a plan made on the home's sphere stands (a sphere, a cylinder's round side about
  // its axis).
  bool Differs(double distance) const {
    return known && std::abs(distance_m - distance) > std::max(2.0 * sigma_m, 0.003);
  }
};

// One contact the model keeps, in the object's frame.
struct SurfaceContact {
  Eigen::Vector3d point, normal, direction;  // direction = point normalized
  double time_s;
};

class SurfaceModel {
 public:
  explicit SurfaceModel(SurfaceModelParams params = {}) : params_(params) {}

  // A fingertip contact: `point` and `outward` (the surface's normal, pointing out of the
  // object: minus the normal into the fingertip) in the palm frame; `object` the object's pose
  // estimate then.
  void Add(const Eigen::Isometry3d& object, const Eigen::Vector3d& point,
           const Eigen::Vector3d& outward, double time_s);
  // The surface along `direction` (object frame) from the object's centre.
  SurfacePoint Along(const Eigen::Vector3d& direction) const;
  // How far `point` (object frame) lies outside the felt tangent planes near it (negative:
  // inside): the surface extended from where it was felt, as a cylinder's side continues past
  // the contacts along it. The planes are weighted by a Gaussian of their contact's distance
  // from the point (width `width_m`) and by how near their normal is to the nearby contacts'
  // mean (kernel_rad). Nothing when the weights sum to less than min_support.
  std::optional<double> OutsidePlanes(const Eigen::Vector3d& point, double width_m) const;
  size_t size() const { return contacts_.size(); }
  const std::vector<SurfaceContact>& contacts() const { return contacts_; }  // oldest first

 private:
  SurfaceModelParams params_;
  std::vector<SurfaceContact> contacts_;
};

}  // namespace dmpl
