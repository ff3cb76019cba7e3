#pragma once
/// The content of a C3D file (https://www.c3d.org, "The C3D File Format User Guide"), mirrored as
/// read: the 512-byte header, the parameter section (groups and parameters) and the 3-D point
/// data. Analog samples are skipped by the reader (their layout is honoured, their values are not
/// kept). Nothing here is converted to the project's neutral types; src/motion/c3d does that.
///
/// Units: point coordinates and residuals are in POINT:UNITS (usually mm), already multiplied by
/// POINT:SCALE for integer storage. Times are seconds.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rt::c3d {

/// Processor type byte of the parameter section (byte 4): sets the byte order and float format.
enum class Processor : std::uint8_t {
  Intel = 84,  ///< little-endian, IEEE floats
  Dec = 85,    ///< little-endian integers, VAX F-floats
  Mips = 86,   ///< big-endian (SGI/MIPS), IEEE floats
};

/// "Intel", "DEC" or "MIPS".
const char* processor_name(Processor p);

/// Parameter element type, as stored (byte `type` of a parameter record).
enum class DataType : std::int8_t { Char = -1, Byte = 1, Int16 = 2, Float = 4 };

/// An event (gait event, trigger...), from the header event block or the EVENT group.
struct Event {
  std::string label;    ///< "Foot Strike", "RHS", ...
  std::string context;  ///< "Left", "Right", "General" or "" (header events have none)
  double time_s = 0;    ///< [s] from the start of the trial (C3D stores minutes + seconds)
  bool from_header = false;  ///< true: header event block; false: EVENT group
};

/// The header block (block 1). Word numbers in the comments are 1-based as in the C3D guide.
struct Header {
  int parameter_block = 0;        ///< byte 1: first block of the parameter section (1-based)
  int point_count = 0;            ///< word 2
  int analog_per_frame = 0;       ///< word 3: analog samples per 3-D frame, all channels together
  int first_frame = 0;            ///< word 4 (1-based, 16 bit)
  int last_frame = 0;             ///< word 5 (16 bit; see TRIAL:ACTUAL_END_FIELD for longer trials)
  int max_interpolation_gap = 0;  ///< word 6
  double scale = 0;               ///< words 7-8: POINT:SCALE copy; negative = float storage
  int data_start_block = 0;       ///< word 9 (1-based)
  int analog_samples_per_frame = 0;  ///< word 10: samples of one analog channel per 3-D frame
  double frame_rate = 0;          ///< words 11-12 [Hz]
  bool has_label_range = false;   ///< word 148 == 12345
  bool four_char_event_labels = false;  ///< word 150 == 12345
  int event_count = 0;            ///< word 151 (at most 18)
};

struct Group {
  int id = 0;               ///< positive group number (stored negated in its record)
  std::string name;
  std::string description;
  bool locked = false;
  std::size_t offset = 0;   ///< byte offset of its record in the file
};

struct Parameter {
  std::string group;        ///< name of its group ("" when the group record is absent)
  int group_id = 0;
  std::string name;
  std::string description;
  DataType type = DataType::Byte;
  std::vector<int> dims;    ///< as stored; empty for a scalar
  bool locked = false;
  std::size_t offset = 0;   ///< byte offset of its record in the file
  /// Values of Byte/Int16/Float parameters in stored (first index fastest) order. Int16 values
  /// keep their sign; use `count_at` for counts that C3D allows to exceed 32767.
  std::vector<double> numbers;
  /// Char parameters: one string per column of the first dimension (dims[0] characters each,
  /// trailing blanks and NULs removed); a 0- or 1-D character parameter is a single string.
  std::vector<std::string> strings;

  /// Number of stored elements (product of dims; 1 for a scalar).
  std::size_t element_count() const;
  /// numbers[i] as an unsigned 16-bit count for Int16 (so 40000 stored as -25536 reads 40000).
  double count_at(std::size_t i) const;
  /// "GROUP:NAME" (used in error locations).
  std::string qualified_name() const { return group + ":" + name; }
};

/// Kind of a 3-D "point": C3D writers also store model outputs (joint angles, forces, moments,
/// powers) as points; they are listed in POINT:ANGLES, POINT:FORCES, ... (and POINT:TYPE_GROUPS).
enum class PointKind : std::uint8_t { Marker, Angle, Force, Moment, Power, Other };

/// 3-D point samples, frame-major.
struct PointSamples {
  int num_points = 0;
  int num_frames = 0;
  /// [POINT:UNITS] xyz[(frame * num_points + point) * 3 + axis]; 0 where the sample is invalid.
  std::vector<float> xyz;
  /// [POINT:UNITS] residual per sample; negative (-1) marks an invalid sample (C3D's convention:
  /// a negative 4th word), never a NaN.
  std::vector<float> residual;

  bool valid(int frame, int point) const {
    return residual[static_cast<std::size_t>(frame) * static_cast<std::size_t>(num_points) +
                    static_cast<std::size_t>(point)] >= 0.0f;
  }
  const float* at(int frame, int point) const {
    return &xyz[(static_cast<std::size_t>(frame) * static_cast<std::size_t>(num_points) +
                 static_cast<std::size_t>(point)) * 3];
  }
};

/// A decoded C3D file.
struct C3dFile {
  std::string name;  ///< file name used in error messages and diagnostics
  std::size_t file_size = 0;
  Processor processor = Processor::Intel;
  Header header;
  std::vector<Group> groups;
  std::vector<Parameter> parameters;

  // ---- the point section, interpreted from the parameters with header fallbacks ----
  std::vector<std::string> point_labels;        ///< one per point; "" when unlabeled
  std::vector<std::string> point_descriptions;  ///< one per point; "" when absent
  std::vector<PointKind> point_kinds;           ///< one per point
  std::string point_units;    ///< POINT:UNITS as stored ("mm"); "" when absent
  double point_rate = 0;      ///< [Hz] POINT:RATE, else header word 11
  double point_scale = 0;     ///< POINT:SCALE, else header words 7-8
  bool float_storage = false; ///< point_scale < 0
  int first_frame = 1;        ///< file frame number of frame 0 (TRIAL:ACTUAL_START_FIELD, else header)
  std::size_t data_offset = 0;  ///< byte offset of the data section
  std::size_t frame_bytes = 0;  ///< bytes per frame (points and analog)

  int analog_channels = 0;            ///< ANALOG:USED (0 without analog data)
  double analog_rate = 0;             ///< [Hz]
  int analog_samples_per_frame = 0;   ///< samples of each channel per 3-D frame

  std::vector<Event> events;  ///< EVENT group if present, else the header event block
  PointSamples points;

  /// The parameter GROUP:NAME (exact, case-insensitive match) or nullptr.
  const Parameter* find(std::string_view group, std::string_view name) const;
  const Group* find_group(std::string_view name) const;
  /// Number of points of kind Marker.
  int marker_count() const;
};

}  // namespace rt::c3d
