#pragma once
// In a recovery, a grip finger that does not touch again is placed again
// (supervisor.replace_after_s): lifted off along the line from the object's centre, moved over
// its home as far out (out to the felt surface where the model knows it lies farther), and
// brought in by a grip; a tip that touches on its way grips there. Brought in to the same point,
// a finger whose links met the object short of its tip meets it the same way again: a finger that
// stops short of the surface is lifted at once and its next point turned toward its base
// (supervisor.replace_shift_rad). A finger that lost its contact far from home
// often rests on the object with a link (no tactile sensor there) and would press on it forever
// with its tip just short of the surface; so would one that touches with a link while its tip
// touches too (supervisor.replace_on_link). With supervisor.replace_on_felt_surface the point it
// goes over is chosen on the felt surface about that point (ContactChooser): where its tip reaches
// and its links stay clear.
#include <string>
#include <vector>

#include "supervisor/blackboard.h"
#include "supervisor/contact_chooser.h"
#include "supervisor/supervisor_params.h"

namespace dmpl {

class FingerReplacer {
 public:
  // The references must outlive the replacer. `chooser` (may be null: the point as planned)
  // chooses on the felt surface, keeping tips `min_spacing_m` apart (their centres).
  FingerReplacer(Blackboard* board, const SupervisorParams& params,
                 const ContactChooser* chooser = nullptr, double min_spacing_m = 0.0);

  void Reset();  // nobody is being placed
  // One tick of the recovery that began at `recovery_since`.
  void Tick(double recovery_since);
  bool placing() const;  // a finger is on its way
  // Finger f grips with a link while its tip pushes too little, long enough to be placed again
  // (supervisor.replace_on_link).
  bool RestsOnLink(int f) const;

 private:
  enum class Stage { kNone, kLift, kOver, kIn };
  bool OthersTouch(int f) const;  // every finger but f touches and none is being placed
  // Brought in, its tip has stopped short of the surface: the point is to move.
  bool Stalled(int f);
  void Lift(int f, const std::string& why);
  void MoveOverHome(int f);
  // Its home's direction from the object's centre, turned toward its base by shift_[f].
  Eigen::Vector3d PlacementDirection(int f) const;
  // The chooser's point on the felt surface in place of the `planned` tip target
  // (replace_on_felt_surface): true, with its tip target and the way out from there (`away`,
  // unit), where it finds one better; false where the planned point stays.
  bool ChooseOnFeltSurface(int f, const Eigen::Vector3d& planned, Eigen::Vector3d* tip,
                           Eigen::Vector3d* away);
  void BringIn(int f);

  Blackboard* board_;
  const SupervisorParams& params_;
  const ContactChooser* chooser_;
  double min_spacing_m_;
  std::vector<Stage> stage_;
  std::vector<double> since_;
  std::vector<double> shift_;                 // rad, toward the base (this recovery)
  std::vector<Eigen::Vector3d> base_side_;    // unit: against the tip's axis when it stalled
  std::vector<Eigen::Vector3d> stall_at_;     // where its tip was when it last moved on
  std::vector<double> stalled_since_;
};

}  // namespace dmpl
