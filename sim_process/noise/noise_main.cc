// dmpl_noise: the noise injector (truth -> sensed channels), as its own process.
#include "sim_process/noise/noise_node.h"

int main(int argc, char** argv) { return dmpl::RunNodeMain(argc, argv, dmpl::kNoiseNode); }
