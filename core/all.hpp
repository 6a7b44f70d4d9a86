// The whole compiled core, its parts in the order of the layers (one translation unit: the
// bindings include it).
#pragma once
#include "api.hpp"

#include "kernel.hpp"
#include "piece.hpp"
#include "linalg.hpp"
#include "corral.hpp"
#include "distance.hpp"
#include "newton.hpp"
#include "shot.hpp"
#include "zc_family.hpp"
#include "gjk_based.hpp"
#include "bi_gjk.hpp"
#include "ie.hpp"
#include "dispatch.hpp"
#include "start_table.hpp"
#include "packed.hpp"
#include "forces.hpp"
#include "warm.hpp"
#include "growth.hpp"
#include "entry.hpp"
#include "contacts.hpp"
