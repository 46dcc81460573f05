#include <cmath>

#include <gtest/gtest.h>

#include "io/json.hpp"
#include "core/error.hpp"

using namespace pbx;

TEST(Json, RoundTripsNestedDocumentsAndNamesErrors) {
  const std::string text = R"({"status": "finished", "x": -1.5e-3, "a": [1, 2.5, null, true],
    "s": {"name": "t\u00e9st \"q\"", "seed": 7}})";
  const Json j = json_parse(text);
  EXPECT_EQ(json_string(*json_find(j, "status")), "finished");
  EXPECT_DOUBLE_EQ(json_number(*json_find(j, "x")), -1.5e-3);
  EXPECT_TRUE(json_array(*json_find(j, "a"))[2].is_null());
  EXPECT_EQ(json_string(*json_find(*json_find(j, "s"), "name")), "t\xc3\xa9st \"q\"");
  const Json back = json_parse(json_dump(j));
  EXPECT_EQ(json_dump(back), json_dump(j));
  EXPECT_EQ(json_dump(Json(0.1)), "0.1");
  EXPECT_EQ(json_dump(Json(std::nan(""))), "null");
  try {
    json_parse("{\"a\": 1,\n \"b\": }", "run.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("run.json:2:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(json_number(*json_find(j, "status"), "run.json: status"), InputError);
  EXPECT_THROW(json_parse("{\"a\": 1e400}", "big.json"), InputError);  // beyond a double: named, not a crash
}

// The written form: integral numbers without ".0" (a temperature reads "293"), arrays of numbers
// on one line, strings untouched even when they hold brackets, control characters escaped.
TEST(Json, WritesIntegralNumbersAsIntegersAndNumberArraysOnOneLine) {
  Json j;
  j["T_K"] = 293.0;
  j["curve"] = json_numbers({0.0, 0.5, std::nan(""), 2.0});
  j["note"] = "range [1,2] and\ta tab";
  j["runs"] = Json::array({Json{{"id", "a"}}});
  const std::string text = json_dump(j);
  EXPECT_NE(text.find("\"T_K\": 293,"), std::string::npos) << text;
  EXPECT_NE(text.find("\"curve\": [0, 0.5, null, 2],"), std::string::npos) << text;
  EXPECT_NE(text.find("\"note\": \"range [1,2] and\\ta tab\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"runs\": [\n    {\n      \"id\": \"a\""), std::string::npos) << text;
  const Json back = json_parse(text);  // the same values back
  EXPECT_EQ(json_number(*json_find(back, "T_K")), 293.0);
  EXPECT_EQ(json_number(json_array(*json_find(back, "curve"))[1]), 0.5);
  EXPECT_TRUE(json_array(*json_find(back, "curve"))[2].is_null());
  EXPECT_EQ(json_string(*json_find(back, "note")), "range [1,2] and\ta tab");
}
