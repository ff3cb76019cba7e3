#include "retarget/core/yaml_view.hpp"

#include <gtest/gtest.h>

namespace rt {
namespace {

TEST(YamlView, ReportsUnknownKeyWithPathAndLine) {
  const auto doc = YamlView::load_string("name: x\nfeet:\n  left:\n    lnk: foo\n", "robot.yaml");
  try {
    doc.at("feet").at("left").check_keys({"link", "sole"});
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "robot.yaml:4: feet.left.lnk: unknown key (allowed: link, sole)");
  }
}

// Issue 18 item 12: yaml-cpp keeps both of two equal keys and lookups see the first one.
TEST(YamlView, DuplicateKeysAreRejectedAtTheSecondOne) {
  try {
    YamlView::load_string("name: x\nfeet:\n  left: a\n  right: b\n  left: c\n", "robot.yaml");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "robot.yaml:5: feet.left: duplicate key");
  }
  EXPECT_THROW(YamlView::load_string("a: 1\na: 2\n", "m.yaml"), InputError);
  EXPECT_THROW(YamlView::load_string("clips:\n  - {path: a.bvh, output: x, output: y}\n", "m.yaml"), InputError);
  // Equal keys in different maps are fine.
  EXPECT_NO_THROW(YamlView::load_string("a: {x: 1}\nb: {x: 2}\nc: [{x: 1}, {x: 2}]\n", "ok.yaml"));
}

TEST(YamlView, ReportsTypeErrors) {
  const auto doc = YamlView::load_string("a: [1, 2, x]\nb: yes_no\n", "c.yaml");
  EXPECT_THROW(doc.at("a").as_doubles(), InputError);
  try {
    doc.at("a").as_doubles();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "c.yaml:1: a[2]: expected a number, got 'x'");
  }
  EXPECT_THROW(doc.at("b").as_bool(), InputError);
  EXPECT_THROW(doc.at("missing"), InputError);
  EXPECT_DOUBLE_EQ(doc.get("missing", 2.5), 2.5);
}

TEST(YamlView, SyntaxErrorHasLine) {
  try {
    YamlView::load_string("a: 1\nb: [1, 2\n", "bad.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml:"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("YAML syntax error"), std::string::npos);
  }
}

TEST(YamlView, RejectsNonFiniteNumbers) {
  const auto doc = YamlView::load_string("a: .nan\nb: .inf\n", "n.yaml");
  EXPECT_THROW(doc.at("a").as_double(), InputError);
  EXPECT_THROW(doc.at("b").as_double(), InputError);
}

// Issue 18 (found by the fuzz driver on robot.yaml): a sequence or map used as a key made
// yaml-cpp throw its own bad-conversion exception (exit 3); it is a located InputError.
TEST(YamlView, ComplexKeysAreLocatedErrors) {
  for (const char* text : {"name: x\n[a, b]: 1\n", "name: x\n? {a: 1}\n: 2\n"}) {
    const auto doc = YamlView::load_string(text, "k.yaml");
    try {
      doc.check_keys({"name"});
      ADD_FAILURE() << "no error for " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.location().rfind("k.yaml:2", 0), 0u) << e.what();
      EXPECT_NE(e.message().find("expected a plain key"), std::string::npos) << e.what();
    }
    EXPECT_THROW(doc.keys(), InputError);
  }
}

}  // namespace
}  // namespace rt
