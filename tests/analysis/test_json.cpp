#include <cmath>

#include <gtest/gtest.h>

#include "analysis/json.hpp"
#include "core/error.hpp"

using namespace pbx;

TEST(Json, RoundTripsNestedDocumentsAndNamesErrors) {
  const std::string text = R"({"status": "finished", "x": -1.5e-3, "a": [1, 2.5, null, true],
    "s": {"name": "t\u00e9st \"q\"", "seed": 7}})";
  const Json j = Json::parse(text);
  EXPECT_EQ(j.find("status")->as_string(), "finished");
  EXPECT_DOUBLE_EQ(j.find("x")->as_number(), -1.5e-3);
  EXPECT_TRUE(j.find("a")->as_array()[2].is_null());
  EXPECT_EQ(j.find("s")->find("name")->as_string(), "t\xc3\xa9st \"q\"");
  const Json back = Json::parse(j.dump());
  EXPECT_EQ(back.dump(), j.dump());
  EXPECT_EQ(Json(0.1).dump(), "0.1");
  EXPECT_EQ(Json(std::nan("")).dump(), "null");
  try {
    Json::parse("{\"a\": 1,\n \"b\": }", "run.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("run.json:2:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(j.find("status")->as_number("run.json: status"), InputError);
}
