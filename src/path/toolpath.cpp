#include "maxslice/path/toolpath.hpp"
