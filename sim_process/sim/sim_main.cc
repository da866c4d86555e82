// dmpl_sim: the simulator of the hand and the object, as its own process.
#include "sim_process/sim/sim_node.h"

int main(int argc, char** argv) { return dmpl::RunNodeMain(argc, argv, dmpl::kSimNode); }
