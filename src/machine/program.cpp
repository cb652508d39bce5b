#include "maxslice/machine/program.hpp"
