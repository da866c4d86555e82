// dmpl_controller: the local manipulation controller, as its own process.
#include "components/controller/controller_node.h"

int main(int argc, char** argv) { return dmpl::RunNodeMain(argc, argv, dmpl::kControllerNode); }
