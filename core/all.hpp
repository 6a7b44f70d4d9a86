// The whole compiled core, its parts in the order of the layers (one translation unit: the
// bindings include it). Every include names its path from core/ (CMakeLists.txt).
#pragma once
#include "api.hpp"

#include "geometry/kernel.hpp"
#include "geometry/piece.hpp"
#include "linalg.hpp"
#include "shooting/corral.hpp"
#include "shooting/distance.hpp"
#include "shooting/newton.hpp"
#include "shooting/shot.hpp"
#include "shooting/zc_family.hpp"
#include "shooting/gjk_based.hpp"
#include "shooting/bi_gjk.hpp"
#include "shooting/ie.hpp"
#include "shooting/dispatch.hpp"
#include "shooting/start_table.hpp"
#include "shooting/packed.hpp"
#include "shooting/warm.hpp"
#include "shooting/entry.hpp"
#include "grasping/forces.hpp"
#include "growth/growth.hpp"
