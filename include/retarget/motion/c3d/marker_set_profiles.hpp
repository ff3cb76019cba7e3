#pragma once
/// Marker-set profiles: recognise the marker set of a C3D file and compute the canonical
/// landmarks (joint centres) from its markers. Built-in profiles:
///
/// - "plug-in-gait" / "cast" (anatomical markers): one engine that knows each anatomical marker
///   under its Vicon Plug-in Gait name (LASI, LKNE, LANK, LSHO, LELB, LWRA, ...), its CAST / ISB
///   name as used by Qualisys (L_IAS, L_FLE, L_FAL, L_SAE/L_SAJ, L_HLE, L_RSP, ...) and common
///   variants (LLFC/LMFC condyles, LLMAL/LMMAL malleoli, LCAL, LMT1...), plus virtual joint-centre
///   markers already in the file (LHJC, LKJC, LAJC, LSJC, LEJC, LWJC), which win when present.
///   Gaps in a marker are first filled from the other markers of its segment (rigid cluster).
///   Joint centres:
///     hip     virtual HJC; else Davis 1991 (Plug-in Gait) when the file carries the subject's leg
///             length (PROCESSING group); else Harrington 2007 from the ASIS and PSIS/sacrum markers
///             (formulas in joint_centre_models.hpp)
///     knee    virtual KJC; else midpoint of lateral and medial markers; else the chord function
///             (HJC, KNE, THI, (knee width + marker diameter) / 2); else KNE moved medially
///     ankle   same pattern one segment down (AJC; ANK+MED; chord(KJC, ANK, TIB); ANK moved)
///     shoulder virtual SJC; else the acromion marker moved down the thorax axis by the shoulder
///             offset + marker radius (Plug-in Gait's default 50 mm + 7 mm)
///     elbow   virtual EJC; else midpoint of the epicondyles; else elbow_joint_centre()
///     wrist   virtual WJC; else the midpoint of the radial/ulnar markers (a Plug-in Gait wrist bar
///             sits on the back of the wrist: moved palmar by wrist thickness / 2 + marker radius)
///     hand    mean of the hand markers (LFIN; L_HM2, L_HM5)
///     toe     toe marker (LTOE, L_FM2); else mean of the forefoot markers (L_FM1/L_FM5, LMT1/LMT2)
///     heel    heel marker (LHEE, L_FCC, LCAL)
///     head    centroid of the head markers; neck: midpoint of C7 and the jugular notch (CLAV/SJN);
///     chest   centroid of C7, CLAV, T10/T8, STRN; spine: midpoint of pelvis and mid(T10, STRN);
///     pelvis  midpoint of the hip joint centres
/// - "optitrack-skeleton": OptiTrack Arena/Motive `<asset>_<Segment><n>` clusters (Hip1-4,
///   Chest1-3, Head1-3, L/RShoulder1-2, L/RUArm1-2, L/RHand1-3, L/RThigh1-2, L/RShin1-2,
///   L/RFoot1-2). The markers of a segment are told apart by geometry, not by number: the pelvis
///   cluster's left/right pair lies towards the thigh clusters, the thigh marker nearest the shin
///   cluster is the lateral knee marker, and so on. Hip centres: midpoint of the lateral waist pair
///   + (0, +-0.25 W, -0.22 W) in the pelvis cluster frame, W the waist-pair distance (anthropometric
///   approximation, about +-3 cm); knee/ankle: the lateral marker moved medially by 57/42 mm;
///   shoulder: the top shoulder marker moved 57 mm down the trunk; elbow: the elbow marker moved
///   45 mm towards the shoulder-wrist line; wrist: midpoint of the two hand markers nearest the
///   elbow; hand: the other hand marker; toe: mean of the foot markers (no heel marker exists).
/// - "segment-clusters": marker clusters named by segment and number (PV1-4 pelvis, [LR]TH1-4
///   thigh, [LR]SK1-4 / [LR]TB shank, [LR]FT1-3 foot; the c3d.org Eb015 sample) with no
///   anatomical markers: hip, knee and ankle centres are found functionally (SCoRE between
///   adjacent clusters, rigid_cluster.hpp); toe = the foot marker farthest from the ankle centre.
///
/// All positions are in metres in the file frame F (no up-axis rotation yet).

#include <array>
#include <string>
#include <vector>

#include "formats/c3d/c3d_file.hpp"
#include "retarget/motion/c3d/marker_map.hpp"
#include "retarget/motion/c3d/marker_trajectories.hpp"
#include "retarget/motion/human_motion.hpp"

namespace rt {

/// Subject measurements stored by Vicon Plug-in Gait in the PROCESSING group; 0 = not given.
/// Index 0 is the left side, 1 the right side.
struct SubjectMeasurements {
  std::array<double, 2> leg_length_m{};
  std::array<double, 2> asis_trocanter_m{};
  double inter_asis_m = 0;
  std::array<double, 2> knee_width_m{};
  std::array<double, 2> ankle_width_m{};
  std::array<double, 2> elbow_width_m{};
  std::array<double, 2> wrist_width_m{};
  std::array<double, 2> shoulder_offset_m{};
  double marker_diameter_m = 0;
};

/// Reads the PROCESSING group (Plug-in Gait writes millimetres). Absent values stay 0.
SubjectMeasurements subject_measurements(const c3d::C3dFile& file);

/// Landmarks computed from markers, in the file frame F.
struct MarkerLandmarks {
  std::string profile;  ///< "plug-in-gait", "cast", "optitrack-skeleton", "segment-clusters", "marker-map:<name>"
  /// Tracks in enum order: present, p_W (here: [m] in the file frame F), state. Orientation unset.
  std::array<LandmarkTrack, kLandmarkCount> tracks;
  /// How each present landmark was computed ("left_hip: Harrington 2007 regression (LASI RASI LPSI RPSI)").
  std::vector<std::string> methods;
  /// Problems met while computing (a cluster that is not rigid, a landmark that failed).
  std::vector<std::string> warnings;
  int rigid_filled_samples = 0;  ///< marker samples reconstructed from their segment cluster
};

/// Recognises the marker set (or applies `map` when given) and computes the landmarks. Fills
/// marker gaps in `markers` from rigid clusters as a side effect. Throws InputError at
/// `error_location` when no profile recognises the markers (the message names the missing
/// landmarks and how to give a marker map) and at the map's file:line when the map names a
/// marker that the file does not have.
MarkerLandmarks compute_marker_landmarks(MarkerTrajectories& markers, const SubjectMeasurements& subject,
                                         const MarkerMap* map, const std::string& error_location);

}  // namespace rt
