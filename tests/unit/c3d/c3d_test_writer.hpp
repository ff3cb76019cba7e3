#pragma once
/// A small C3D writer for tests: builds well-formed files for any processor type and storage
/// (to test the reader against known content) and exposes the offsets of what it wrote (to make
/// precisely malformed variants). Not a production writer: no analog values, no label ranges.

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "formats/c3d/c3d_file.hpp"

namespace rt::test {

/// One extra parameter (raw typed values).
struct C3dParam {
  std::string group;
  std::string name;
  c3d::DataType type = c3d::DataType::Int16;
  std::vector<int> dims;           ///< empty = scalar
  std::vector<double> numbers;     ///< Byte/Int16/Float
  std::vector<std::string> strings;  ///< Char: padded to dims[0]
};

struct C3dSpec {
  c3d::Processor processor = c3d::Processor::Intel;
  bool float_storage = true;
  double int_scale = 0.1;  ///< [units/count] for integer storage (POINT:SCALE > 0)
  double rate = 100;
  int first_frame = 1;
  std::string units = "mm";
  std::vector<std::string> labels;  ///< one per point (POINT:LABELS); empty strings allowed
  int labels_per_parameter = 255;   ///< split into LABELS, LABELS2, ... beyond this many
  /// samples[frame][point] = {x, y, z, residual}; residual < 0 marks an invalid sample.
  std::vector<std::vector<std::array<float, 4>>> samples;
  int analog_channels = 0;           ///< ANALOG:USED; analog words are written as a ramp
  int analog_samples_per_frame = 0;  ///< ANALOG:RATE = rate * this
  bool write_parameters = true;      ///< false: empty parameter section (like the PhaseSpace sample)
  bool data_start_param_zero = false;  ///< POINT:DATA_START = 0 (header word 9 still right)
  bool trial_fields = false;         ///< write TRIAL:ACTUAL_START_FIELD / ACTUAL_END_FIELD
  int header_frames_override = -1;   ///< unless -1: frames claimed by the header (last = first + n - 1)
  bool point_used_float = false;     ///< store POINT:USED as a float (some writers do)
  std::vector<std::pair<std::string, double>> events;  ///< EVENT group (label, seconds)
  std::vector<C3dParam> extra;
};

/// What was written, with offsets for corrupting it.
struct C3dBytes {
  std::string bytes;
  std::map<std::string, std::size_t> record_offset;  ///< "GROUP:NAME" or "GROUP" -> record start
  std::map<std::string, std::size_t> link_offset;    ///< "GROUP:NAME" -> offset of its next-record word
  std::size_t parameter_offset = 0;                  ///< start of the parameter section
  std::size_t parameter_end = 0;                     ///< end of the parameter section
  std::size_t data_offset = 0;
};

class C3dWriter {
 public:
  explicit C3dWriter(c3d::Processor p) : p_(p) {}

  void put_i16(std::string& out, int v) const {
    const auto u = static_cast<std::uint16_t>(static_cast<std::int16_t>(v));
    if (p_ == c3d::Processor::Mips) {
      out.push_back(static_cast<char>(u >> 8));
      out.push_back(static_cast<char>(u & 0xff));
    } else {
      out.push_back(static_cast<char>(u & 0xff));
      out.push_back(static_cast<char>(u >> 8));
    }
  }
  void put_f32(std::string& out, float v) const {
    std::uint32_t u;
    if (p_ == c3d::Processor::Dec) {
      // VAX F-float: IEEE bits of 4v with the 16-bit words swapped (v = 0 stays 0).
      const float scaled = v * 4.0f;
      std::memcpy(&u, &scaled, 4);
      if (v == 0.0f) u = 0;
      const std::uint32_t swapped = (u >> 16) | (u << 16);
      for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((swapped >> (8 * k)) & 0xff));
      return;
    }
    std::memcpy(&u, &v, 4);
    if (p_ == c3d::Processor::Mips)
      for (int k = 3; k >= 0; --k) out.push_back(static_cast<char>((u >> (8 * k)) & 0xff));
    else
      for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((u >> (8 * k)) & 0xff));
  }
  void set_i16(std::string& out, std::size_t at, int v) const {
    std::string tmp;
    put_i16(tmp, v);
    out.replace(at, 2, tmp);
  }
  void set_f32(std::string& out, std::size_t at, float v) const {
    std::string tmp;
    put_f32(tmp, v);
    out.replace(at, 4, tmp);
  }

 private:
  c3d::Processor p_;
};

inline C3dBytes write_c3d(const C3dSpec& spec) {
  const C3dWriter w(spec.processor);
  C3dBytes result;
  const int points = spec.samples.empty() ? static_cast<int>(spec.labels.size())
                                          : static_cast<int>(spec.samples[0].size());
  const int frames = static_cast<int>(spec.samples.size());
  const double scale = spec.float_storage ? -std::abs(spec.int_scale) : std::abs(spec.int_scale);
  const int analog_words = spec.analog_channels * spec.analog_samples_per_frame;

  // ---- parameters ----
  struct Group {
    int id;
    std::string name;
    std::vector<C3dParam> params;
  };
  std::vector<Group> groups;
  auto add = [&](const C3dParam& p) {
    for (Group& g : groups)
      if (g.name == p.group) {
        g.params.push_back(p);
        return;
      }
    groups.push_back({static_cast<int>(groups.size()) + 1, p.group, {p}});
  };
  auto scalar = [](const std::string& g, const std::string& n, c3d::DataType t, double v) {
    return C3dParam{g, n, t, {}, {v}, {}};
  };
  auto text = [](const std::string& g, const std::string& n, const std::vector<std::string>& s, int width) {
    C3dParam p{g, n, c3d::DataType::Char, {}, {}, s};
    if (s.size() == 1 && width <= 0) p.dims = {static_cast<int>(s[0].size())};
    else p.dims = {width, static_cast<int>(s.size())};
    return p;
  };
  const int data_start_block_placeholder = 0;  // patched below
  if (spec.write_parameters) {
    add(scalar("POINT", "USED", spec.point_used_float ? c3d::DataType::Float : c3d::DataType::Int16, points));
    add(scalar("POINT", "SCALE", c3d::DataType::Float, scale));
    add(scalar("POINT", "RATE", c3d::DataType::Float, spec.rate));
    add(scalar("POINT", "DATA_START", c3d::DataType::Int16, data_start_block_placeholder));
    add(scalar("POINT", "FRAMES", c3d::DataType::Int16, frames));
    add(text("POINT", "UNITS", {spec.units}, 0));
    for (std::size_t i = 0, k = 1; i < spec.labels.size(); i += static_cast<std::size_t>(spec.labels_per_parameter), ++k) {
      const auto end = std::min(spec.labels.size(), i + static_cast<std::size_t>(spec.labels_per_parameter));
      std::vector<std::string> chunk(spec.labels.begin() + static_cast<std::ptrdiff_t>(i),
                                     spec.labels.begin() + static_cast<std::ptrdiff_t>(end));
      add(text("POINT", k == 1 ? "LABELS" : "LABELS" + std::to_string(k), chunk, 16));
    }
    if (spec.analog_channels > 0) {
      add(scalar("ANALOG", "USED", c3d::DataType::Int16, spec.analog_channels));
      add(scalar("ANALOG", "RATE", c3d::DataType::Float, spec.rate * spec.analog_samples_per_frame));
    }
    if (spec.trial_fields) {
      const int last = spec.first_frame + frames - 1;
      add(C3dParam{"TRIAL", "ACTUAL_START_FIELD", c3d::DataType::Int16, {2},
                   {static_cast<double>(spec.first_frame & 0xffff), static_cast<double>(spec.first_frame >> 16)}, {}});
      add(C3dParam{"TRIAL", "ACTUAL_END_FIELD", c3d::DataType::Int16, {2},
                   {static_cast<double>(last & 0xffff), static_cast<double>(last >> 16)}, {}});
    }
    if (!spec.events.empty()) {
      std::vector<std::string> labels;
      std::vector<double> times;
      for (const auto& [label, t] : spec.events) {
        labels.push_back(label);
        times.push_back(std::floor(t / 60));
        times.push_back(t - 60 * std::floor(t / 60));
      }
      add(scalar("EVENT", "USED", c3d::DataType::Int16, static_cast<double>(spec.events.size())));
      add(text("EVENT", "LABELS", labels, 16));
      add(C3dParam{"EVENT", "TIMES", c3d::DataType::Float, {2, static_cast<int>(spec.events.size())}, times, {}});
    }
    for (const C3dParam& p : spec.extra) add(p);
  }

  std::string params;  // relative to the parameter section start
  params += static_cast<char>(1);
  params += static_cast<char>(0x50);
  params += static_cast<char>(0);  // block count, patched
  params += static_cast<char>(static_cast<int>(spec.processor));
  std::size_t data_start_value_at = 0;
  std::vector<std::size_t> links;
  for (const Group& g : groups) {
    result.record_offset[g.name] = params.size();
    params += static_cast<char>(g.name.size());
    params += static_cast<char>(-g.id);
    params += g.name;
    links.push_back(params.size());
    w.put_i16(params, 3);  // next: 2 (link) + 1 (description length)
    params += static_cast<char>(0);
  }
  for (const Group& g : groups)
    for (const C3dParam& p : g.params) {
      const std::string key = g.name + ":" + p.name;
      result.record_offset[key] = params.size();
      params += static_cast<char>(p.name.size());
      params += static_cast<char>(g.id);
      params += p.name;
      const std::size_t link = params.size();
      result.link_offset[key] = link;
      links.push_back(link);
      w.put_i16(params, 0);  // patched
      params += static_cast<char>(static_cast<int>(p.type));
      params += static_cast<char>(p.dims.size());
      for (int d : p.dims) params += static_cast<char>(d);
      if (p.type == c3d::DataType::Char) {
        const std::size_t width = p.dims.empty() ? 1 : static_cast<std::size_t>(p.dims[0]);
        for (const std::string& s : p.strings) {
          std::string padded = s.substr(0, width);
          padded.resize(width, ' ');
          params += padded;
        }
      } else {
        if (key == "POINT:DATA_START") data_start_value_at = params.size();
        for (double v : p.numbers) {
          if (p.type == c3d::DataType::Byte) params += static_cast<char>(static_cast<int>(v));
          else if (p.type == c3d::DataType::Int16) w.put_i16(params, static_cast<int>(v));
          else w.put_f32(params, static_cast<float>(v));
        }
      }
      params += static_cast<char>(0);  // description length
      w.set_i16(params, link, static_cast<int>(params.size() - link));
    }
  if (!links.empty()) w.set_i16(params, links.back(), 0);  // last record
  params += std::string(2, '\0');  // end marker
  const std::size_t param_blocks = spec.write_parameters ? (params.size() + 511) / 512 : 0;
  params.resize(std::max<std::size_t>(param_blocks, 1) * 512, '\0');
  params[2] = static_cast<char>(param_blocks);
  const int data_start_block = 2 + static_cast<int>(std::max<std::size_t>(param_blocks, 1));
  if (data_start_value_at) w.set_i16(params, data_start_value_at, spec.data_start_param_zero ? 0 : data_start_block);

  // ---- header ----
  std::string header(512, '\0');
  header[0] = 2;
  header[1] = 0x50;
  const int header_frames = spec.header_frames_override != -1 ? spec.header_frames_override : frames;
  w.set_i16(header, 2, points);
  w.set_i16(header, 4, analog_words);
  w.set_i16(header, 6, spec.first_frame);
  w.set_i16(header, 8, spec.first_frame + header_frames - 1);
  w.set_i16(header, 10, 10);
  w.set_f32(header, 12, static_cast<float>(scale));
  w.set_i16(header, 16, data_start_block);
  w.set_i16(header, 18, spec.analog_samples_per_frame);
  w.set_f32(header, 20, static_cast<float>(spec.rate));

  // ---- data ----
  std::string data;
  for (int f = 0; f < frames; ++f) {
    for (int i = 0; i < points; ++i) {
      const auto& s = spec.samples[static_cast<std::size_t>(f)][static_cast<std::size_t>(i)];
      if (spec.float_storage) {
        for (int k = 0; k < 3; ++k) w.put_f32(data, s[static_cast<std::size_t>(k)]);
        w.put_f32(data, s[3] < 0 ? -1.0f : s[3] / static_cast<float>(std::abs(spec.int_scale)));
      } else {
        for (int k = 0; k < 3; ++k)
          w.put_i16(data, static_cast<int>(std::lround(s[static_cast<std::size_t>(k)] / spec.int_scale)));
        w.put_i16(data, s[3] < 0 ? -1 : static_cast<int>(std::lround(s[3] / spec.int_scale)) & 0xff);
      }
    }
    for (int a = 0; a < analog_words; ++a) {
      if (spec.float_storage) w.put_f32(data, static_cast<float>(a));
      else w.put_i16(data, a);
    }
  }
  data.resize((data.size() + 511) / 512 * 512, '\0');

  result.parameter_offset = 512;
  result.parameter_end = 512 + param_blocks * 512;
  for (auto& [k, v] : result.record_offset) v += 512;
  for (auto& [k, v] : result.link_offset) v += 512;
  result.bytes = header + params + data;
  result.data_offset = (static_cast<std::size_t>(data_start_block) - 1) * 512;
  return result;
}

}  // namespace rt::test
