#include "retarget/core/error.hpp"

#include <gtest/gtest.h>

#include "retarget/core/yaml_view.hpp"

namespace rt {
namespace {

// Issue 18 (found by the fuzz driver): messages echo names and values from the input, and a name
// holding a line break ("fi\nxed", a YAML key "\"a\\rb\"") made the one-line error two lines.
// Control characters are written as escapes in what(), location() and message().
TEST(InputError, ControlCharactersFromTheInputAreEscaped) {
  const InputError e("m.yaml:5", "unknown key 'time\n_scale\r' (tab\there, bell\x07)");
  EXPECT_EQ(std::string(e.what()), "m.yaml:5: unknown key 'time\\n_scale\\r' (tab\\there, bell\\x07)");
  EXPECT_EQ(e.message(), "unknown key 'time\\n_scale\\r' (tab\\there, bell\\x07)");
  EXPECT_EQ(InputError("a\nb.bvh:1", "x").location(), "a\\nb.bvh:1");
  EXPECT_EQ(std::string(InputError("plain").what()), "plain");
  // Through a parser: a quoted YAML key with an escaped line break.
  try {
    const YamlView y = YamlView::load_string("\"ti\\nme\": 1\n", "k.yaml");
    y.check_keys({"time"});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("ti\\nme"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rt
