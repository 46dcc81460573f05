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
}
