#include "pipeline/diagnostic.h"
