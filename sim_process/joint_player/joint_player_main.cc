// dmpl_joint_player: joint trajectories played to the simulator, as its own process.
#include "sim_process/joint_player/joint_player_node.h"

int main(int argc, char** argv) { return dmpl::RunNodeMain(argc, argv, dmpl::kJointPlayerNode); }
