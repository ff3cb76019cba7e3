#pragma once
/// The plots of a dynamics-check report, as svg::Figure values (render with svg::render). All
/// figures share the time axis [0, clip duration] so they line up when viewed side by side; a
/// run that fell leaves the rest of the axis empty after the fall marker.

#include "retarget/report/check_report.hpp"
#include "retarget/report/svg_plot.hpp"

namespace rt {

/// Fig. 7 of the paper along one horizontal world axis (0 = x, forward; 1 = y, sideways, + left,
/// for a robot facing +x; traces are in the world frame, so a robot that turns is not re-projected):
/// actual COM, reference COM after re-planning, original reference COM, measured and desired COP
/// over time, the support polygon's extent along the axis shaded (gaps where nothing supports),
/// re-planning activations as vertical markers (activations less than 50 ms apart form a burst:
/// one marker at its start and a light span over it; tooltips give the count and largest shift),
/// COP-near-edge violations shaded and the fall marked.
svg::Figure com_cop_figure(const DynamicsCheckResult& result, const ReportInfo& info, int axis);

/// Contact timeline: reference vs actual (loaded) contact per foot as bars, with unmet contact,
/// lift-off and slip violations shaded; below it the normal force on each foot.
svg::Figure contacts_figure(const DynamicsCheckResult& result, const ReportInfo& info);

/// RMS joint tracking error per joint group (legs, torso, arms, all) in degrees, with torque
/// saturation and joint-limit violations shaded; below it the horizontal COM error (actual vs
/// re-planned reference) and COP error (measured vs desired) in millimetres.
svg::Figure tracking_figure(const DynamicsCheckResult& result, const ReportInfo& info);

}  // namespace rt
