#pragma once
// In a recovery, a grip finger that does not touch again is placed again
// (supervisor.replace_after_s): lifted off along the line from the object's centre, moved over
// its home as far out, and brought in by a grip. A finger that lost its contact far from home
// often rests on the object with a link (no tactile sensor there) and would press on it forever
// with its tip just short of the surface; so would one that touches with a link while its tip
// touches too (supervisor.replace_on_link).
#include <string>
#include <vector>

#include "supervisor/blackboard.h"
#include "supervisor/supervisor_params.h"

namespace dmpl {

class FingerReplacer {
 public:
  // The references must outlive the replacer.
  FingerReplacer(Blackboard* board, const SupervisorParams& params);

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
  void Lift(int f, const std::string& why);
  void MoveOverHome(int f);
  void BringIn(int f);

  Blackboard* board_;
  const SupervisorParams& params_;
  std::vector<Stage> stage_;
  std::vector<double> since_;
};

}  // namespace dmpl
