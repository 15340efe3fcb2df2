// Deliberately wrong: core reaches up into lattice.
#include "lattice/field_job.hpp"
