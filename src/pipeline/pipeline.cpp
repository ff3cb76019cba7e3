#include "retarget/pipeline/pipeline.hpp"

#include <algorithm>
#include <chrono>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt {

const PassInfo* find_pass(const PassRegistry& registry, const std::string& name) {
  for (const PassInfo& p : registry)
    if (p.name == name) return &p;
  return nullptr;
}

namespace {

std::unique_ptr<Pass> make_pass(const PassRegistry& registry, const std::string& name) {
  const PassInfo* info = find_pass(registry, name);
  if (!info) {
    std::vector<std::string> names;
    for (const PassInfo& p : registry) names.push_back(p.name);
    throw InputError("--passes", "unknown pass '" + name + "' (passes: " + join(names, ", ") + ")");
  }
  return info->make();
}

}  // namespace

Pipeline Pipeline::parse(const std::string& spec, const PassRegistry& registry) {
  Pipeline pipeline;
  std::size_t i = 0;
  const auto skip_space = [&] {
    while (i < spec.size() && (spec[i] == ' ' || spec[i] == '\t')) ++i;
  };
  while (i < spec.size()) {
    skip_space();
    const std::size_t start = i;
    while (i < spec.size() && spec[i] != ',' && spec[i] != '{') ++i;
    const std::string name(trim(std::string_view(spec).substr(start, i - start)));
    if (name.empty()) throw InputError("--passes", "empty pass name at character " + std::to_string(start + 1) + " of '" + spec + "'");
    std::unique_ptr<Pass> pass = make_pass(registry, name);
    if (i < spec.size() && spec[i] == '{') {
      const std::size_t close = spec.find('}', i);
      if (close == std::string::npos) throw InputError("--passes", "missing '}' after the options of pass '" + name + "'");
      for (const std::string& kv : split(std::string_view(spec).substr(i + 1, close - i - 1), ",")) {
        const auto eq = kv.find('=');
        if (eq == std::string::npos) throw InputError("--passes", "pass '" + name + "': expected key=value, got '" + kv + "'");
        pass->options().set(std::string(trim(std::string_view(kv).substr(0, eq))),
                            std::string(trim(std::string_view(kv).substr(eq + 1))), "--passes " + name);
      }
      i = close + 1;
    }
    skip_space();
    if (i < spec.size()) {
      if (spec[i] != ',') throw InputError("--passes", "expected ',' after pass '" + name + "'");
      ++i;
    }
    pipeline.add(std::move(pass));
  }
  return pipeline;
}

Pipeline Pipeline::default_pipeline(const PassRegistry& registry, const std::vector<std::string>& disabled,
                                    const std::vector<std::string>& enabled) {
  for (const auto* names : {&disabled, &enabled})
    for (const std::string& d : *names)
      if (!find_pass(registry, d)) make_pass(registry, d);  // throws the "unknown pass" error
  auto listed = [](const std::vector<std::string>& v, const std::string& n) { return std::find(v.begin(), v.end(), n) != v.end(); };
  Pipeline pipeline;
  for (const PassInfo& p : registry)
    if ((p.in_default_pipeline || listed(enabled, p.name)) && !listed(disabled, p.name)) pipeline.add(p.make());
  return pipeline;
}

int Pipeline::set_option_everywhere(const std::string& option, const std::string& value) {
  int taken = 0;
  for (auto& p : passes_)
    for (const auto& e : p->options().entries())
      if (e.name == option) {
        p->options().set(option, value, p->name());
        ++taken;
        break;
      }
  return taken;
}

Pass* Pipeline::find(const std::string& name) {
  for (auto& p : passes_)
    if (p->name() == name) return p.get();
  return nullptr;
}

std::vector<std::string> Pipeline::names() const {
  std::vector<std::string> out;
  for (const auto& p : passes_) out.push_back(p->name());
  return out;
}

std::string Pipeline::to_string() const {
  std::vector<std::string> parts;
  for (const auto& p : passes_) {
    const std::string opts = p->options().to_string();
    parts.push_back(opts.empty() ? p->name() : p->name() + "{" + opts + "}");
  }
  return join(parts, ",");
}

const RobotModel& PassContext::model() const {
  RT_DEMAND(robot_model != nullptr, "pass run without a robot model");
  return *robot_model;
}

RobotData& PassContext::data() const {
  RT_DEMAND(robot_data != nullptr, "pass run without robot data");
  return *robot_data;
}

std::vector<PassRecord> Pipeline::run(Clip& clip, const RobotModel* model, RobotData* data) const {
  return run(clip, model, data, PassStarted());
}

std::vector<PassRecord> Pipeline::run(Clip& clip, const RobotModel* model, RobotData* data, const PassStarted& on_pass) const {
  std::vector<PassRecord> records;
  for (const auto& pass : passes_) {
    if (on_pass) on_pass(static_cast<int>(records.size()), static_cast<int>(passes_.size()), pass->name());
    PassRecord record;
    record.name = pass->name();
    record.options = pass->options().to_string();
    PassContext context{model, data, record.statistics, clip.diagnostics};
    const auto t0 = std::chrono::steady_clock::now();
    pass->run(clip, context);
    record.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    records.push_back(std::move(record));
  }
  return records;
}

}  // namespace rt
