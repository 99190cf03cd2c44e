// demsa — sensitivity analysis and calibration of DEM models in LIGGGHTS. Everything lives in the libraries.
#include "orchestrator/cli/cli.hpp"

int main(int argc, char** argv) { return demsa::cli::run_cli(argc, argv); }
