// dmpl_ik: the IK server, as its own process.
#include "components/ik/ik_node.h"

int main(int argc, char** argv) { return dmpl::RunNodeMain(argc, argv, dmpl::kIkNode); }
