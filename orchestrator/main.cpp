// demsa — sensitivity analysis and calibration of DEM models in LIGGGHTS. Everything lives in the libraries.
#include "orchestrator/cli.hpp"

int main(int argc, char** argv) { return demsa::run_cli(argc, argv); }
