// Internal helpers shared by the core's translation units. Not installed.
#pragma once
#include <cstdarg>
#include <string>
