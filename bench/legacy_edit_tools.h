// SPDX-License-Identifier: MIT
#pragma once
// The single-stamp edit tools, for same-run comparisons in bench_edit only.
#include <hdm/edit/edit_tools.h>

namespace hdm::bench::legacy {
EditResult carve(SlabModel& model, EditScratch& scratch, const Contact& contact, const Vec3& hip, double radius,
                 double resilience) noexcept;
EditResult add_material(SlabModel& model, EditScratch& scratch, const Contact& contact, double radius,
                        double height) noexcept;
EditResult paint(SlabModel& model, EditScratch& scratch, const Contact& contact, double radius, const Vec3f& colour,
                 double pressure) noexcept;
}  // namespace hdm::bench::legacy
