#include "retarget/pipeline/pipeline.hpp"

#include <gtest/gtest.h>

#include "retarget/core/error.hpp"

namespace rt {
namespace {

struct CountOptions {
  int increment = 1;       ///< added to the clip's frame count
  double factor = 1.0;
  bool enabled = true;
};

// A toy pass that edits the clip in a visible way, so ordering and options can be checked.
class CountPass final : public Pass {
 public:
  explicit CountPass(std::string name) : name_(std::move(name)) {
    table_.add("increment", options_.increment, "frames added");
    table_.add("factor", options_.factor, "scale");
    table_.add("enabled", options_.enabled, "on/off");
  }
  std::string name() const override { return name_; }
  std::string description() const override { return "adds frames"; }
  OptionTable& options() override { return table_; }
  void run(Clip& clip, PassContext& ctx) override {
    if (options_.enabled) clip.human.num_frames = static_cast<int>((clip.human.num_frames + options_.increment) * options_.factor);
    clip.name += name_ + ";";
    ctx.statistics.set("frames", clip.human.num_frames, "frames");
  }

 private:
  std::string name_;
  CountOptions options_;
  OptionTable table_;
};

PassRegistry registry() {
  return {{"a", "first", true, [] { return std::make_unique<CountPass>("a"); }},
          {"b", "second", true, [] { return std::make_unique<CountPass>("b"); }},
          {"c", "optional", false, [] { return std::make_unique<CountPass>("c"); }}};
}

TEST(Pipeline, ParsesSpecWithOptions) {
  const Pipeline p = Pipeline::parse("b{increment=5, factor=2}, a ,c{enabled=false}", registry());
  EXPECT_EQ(p.names(), (std::vector<std::string>{"b", "a", "c"}));
  EXPECT_EQ(p.to_string(), "b{increment=5,factor=2,enabled=true},a{increment=1,factor=1,enabled=true},"
                           "c{increment=1,factor=1,enabled=false}");
  Clip clip;
  clip.human.num_frames = 1;
  const auto records = p.run(clip, nullptr, nullptr);  // these passes need no robot
  EXPECT_EQ(clip.human.num_frames, (1 + 5) * 2 + 1);
  EXPECT_EQ(clip.name, "b;a;c;");
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(records[0].statistics.get("frames"), 12);
  EXPECT_GE(records[0].time_ms, 0);
}

TEST(Pipeline, DefaultPipelineAndDisabling) {
  EXPECT_EQ(Pipeline::default_pipeline(registry()).names(), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(Pipeline::default_pipeline(registry(), {"a"}).names(), (std::vector<std::string>{"b"}));
  EXPECT_THROW(Pipeline::default_pipeline(registry(), {"zz"}), InputError);
}

TEST(Pipeline, ErrorsNameTheProblem) {
  auto message = [](const std::string& spec) {
    try {
      Pipeline::parse(spec, registry());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("a,x"), "--passes: unknown pass 'x' (passes: a, b, c)");
  EXPECT_EQ(message("a{increment=}"), "--passes a: option increment: expected a number, got ''");
  EXPECT_EQ(message("a{speed=3}"), "--passes a: unknown option 'speed' (options: increment, factor, enabled)");
  EXPECT_EQ(message("a{increment=1.5}"), "--passes a: option increment: expected an integer, got '1.5'");
  EXPECT_EQ(message("a{increment=1"), "--passes: missing '}' after the options of pass 'a'");
  EXPECT_EQ(message("a,,b"), "--passes: empty pass name at character 3 of 'a,,b'");
}

TEST(Pipeline, SetOptionEverywhere) {
  Pipeline p = Pipeline::parse("a,b", registry());
  EXPECT_EQ(p.set_option_everywhere("factor", "3"), 2);
  EXPECT_EQ(p.set_option_everywhere("nothing", "3"), 0);
  EXPECT_THROW(p.set_option_everywhere("factor", "x"), InputError);
}

}  // namespace
}  // namespace rt
