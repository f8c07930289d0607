#include "ui/batch/csv.h"

#include <gtest/gtest.h>

#include "core/util/check.h"

namespace sylva {
namespace {

TEST(CsvTest, ReadsQuotedFieldsLineEndsAndComments) {
  const std::string text =
      "\xEF\xBB\xBFname,photos\r\n"
      "# a comment\n"
      "\n"
      "a,\"x, \"\"y\"\"\"\r\n"
      "b,\"two\nlines\"\n"
      "c,\n"
      "d";
  const std::vector<CsvRecord> records = ParseCsv(text, "m.csv");
  ASSERT_EQ(records.size(), 5u);
  EXPECT_EQ(records[0].fields, (std::vector<std::string>{"name", "photos"}));
  EXPECT_EQ(records[0].line, 1);
  EXPECT_EQ(records[1].fields, (std::vector<std::string>{"a", "x, \"y\""}));
  EXPECT_EQ(records[1].line, 4);
  EXPECT_EQ(records[2].fields, (std::vector<std::string>{"b", "two\nlines"}));
  EXPECT_EQ(records[2].line, 5);
  EXPECT_EQ(records[3].fields, (std::vector<std::string>{"c", ""}));
  EXPECT_EQ(records[3].line, 7);
  EXPECT_EQ(records[4].fields, (std::vector<std::string>{"d"}));
  EXPECT_EQ(records[4].line, 8);
}

TEST(CsvTest, NamesTheLineOfBadQuotes) {
  try {
    ParseCsv("name\na\n\"open\n", "m.csv");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "m.csv:3");
  }
  try {
    ParseCsv("name\n\"a\"b\n", "m.csv");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(error.source(), "m.csv:2");
  }
}

TEST(CsvTest, WritesWhatItReads) {
  const std::vector<std::string> fields = {
      "plain", "a,b", "say \"hi\"", "two\nlines", " pad", "#not a comment", ""};
  const std::vector<CsvRecord> records = ParseCsv(CsvLine(fields), "x");
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0].fields, fields);
}

}  // namespace
}  // namespace sylva
