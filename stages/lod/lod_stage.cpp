// Placeholder adapter (filled in next).
#include "stages/lod/lod_stage.h"
