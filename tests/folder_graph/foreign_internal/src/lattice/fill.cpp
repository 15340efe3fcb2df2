// Deliberately wrong: lattice reaches into core's internal headers.
#include "core/internal/threads.hpp"
