// stltopo: the whole public API (same as <stltopo/stltopo.h>).
#pragma once

#include "stltopo/stltopo.h"
