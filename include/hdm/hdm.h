// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// hdm's runtime in one include: what a haptics or sculpting program needs to load a baked slab
/// model, query it, render forces through the proxy in a servo loop, edit it and save it. Link
/// `hdm::core` and `hdm::io` (no Embree, TBB or CGAL). Baking a mesh (hdm/slab/bake.h, hdm::bake),
/// exporting and rendering have their own headers.
///
/// The data flow these headers follow (docs/architecture.md): slab model -> query -> proxy and
/// forces, edits -> files.

#include <hdm/core/error.h>
#include <hdm/core/types.h>
#include <hdm/edit/brush.h>
#include <hdm/edit/brush_registry.h>
#include <hdm/edit/edit_tools.h>
#include <hdm/edit/stroke_editor.h>
#include <hdm/edit/undo_history.h>
#include <hdm/haptics/device.h>
#include <hdm/haptics/force.h>
#include <hdm/haptics/proxy.h>
#include <hdm/haptics/servo_loop.h>
#include <hdm/haptics/sphere_proxy.h>
#include <hdm/io/hdm_file.h>
#include <hdm/query/slab_locator.h>
#include <hdm/query/slab_query.h>
#include <hdm/session/sculpt_session.h>
#include <hdm/slab/slab_model.h>
#include <hdm/slab/slab_snapshots.h>
