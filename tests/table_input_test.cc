// Tables as people write them: spreadsheet separators and quotes, units in
// column names, and the warnings for radians read as degrees, percent and
// an arbitrary scale (io/table.h).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "io/input_error.h"
#include "io/table.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The same three rows in every test: angles in degrees, values in [0, 1].
const char kRows[] =
    "10,0,20,180,0.25\n"
    "45,90,60,-90,0.5\n"
    "70,0,30,0,0.125\n";

std::string Replace(std::string text, char from, const std::string& to) {
  std::string out;
  for (char c : text) {
    if (c == from) {
      out += to;
    } else {
      out += c;
    }
  }
  return out;
}

std::string ParseError(const std::string& text) {
  try {
    ParseTable(text, "data.csv");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// The parsed rows equal the comma-separated degrees table's.
void ExpectSameRows(const MeasurementTable& table) {
  const MeasurementTable reference =
      ParseTable(std::string("theta_i,phi_i,theta_o,phi_o,value\n") + kRows,
                 "reference.csv")
          .table;
  ASSERT_EQ(table.rows.size(), reference.rows.size());
  for (size_t i = 0; i < table.rows.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(table.rows[i].wi[k], reference.rows[i].wi[k], 1e-12);
      EXPECT_NEAR(table.rows[i].wo[k], reference.rows[i].wo[k], 1e-12);
      EXPECT_NEAR(table.rows[i].value[k], reference.rows[i].value[k], 1e-12);
    }
  }
}

TEST(TableInput, SemicolonAndTabSeparatedTablesReadAsCommaSeparated) {
  const std::string header = "theta_i,phi_i,theta_o,phi_o,value\n";
  for (const char* separator : {";", "\t"}) {
    const std::string text = Replace(header + kRows, ',', separator);
    ExpectSameRows(ParseTable(text, "data.csv").table);
  }
}

TEST(TableInput, SemicolonTablesMayUseDecimalCommas) {
  const std::string text =
      "theta_i;phi_i;theta_o;phi_o;value\n"
      "10;0;20;180;0,25\n"
      "45;90;60;-90;0,5\n"
      "70;0;30;0;0,125\n";
  ExpectSameRows(ParseTable(text, "data.csv").table);
  // With commas as separators a decimal comma is a field too many.
  EXPECT_NE(ParseError("theta_i,phi_i,theta_o,phi_o,value\n10,0,20,180,0,25\n")
                .find("fields"),
            std::string::npos);
}

TEST(TableInput, QuotedNamesAndValuesAreRead) {
  const std::string text =
      "\"theta_i\",\"phi_i\",\"theta_o\",\"phi_o\",\"value\"\n"
      "\"10\",0,20,180,0.25\n"
      "45,90,60,-90,\"0.5\"\n"
      "70,0,30,0,0.125\n";
  ExpectSameRows(ParseTable(text, "data.csv").table);
}

TEST(TableInput, UnitsInBracketsSetTheAngleUnit) {
  ExpectSameRows(ParseTable(std::string("theta_i [deg],phi_i [deg],theta_o "
                                        "(degrees),phi_o [\xC2\xB0],value "
                                        "[1/sr]\n") +
                                kRows,
                            "data.csv")
                     .table);
  // The same table in radians, said by the column names alone.
  std::string radians =
      "\"theta_i (rad)\";phi_i (rad);theta_o [rad];phi_o "
      "[radians];value\n";
  const double rows[3][5] = {
      {10, 0, 20, 180, 0.25}, {45, 90, 60, -90, 0.5}, {70, 0, 30, 0, 0.125}};
  for (const auto& row : rows) {
    for (int k = 0; k < 4; ++k) {
      radians += text_util::FormatNumber(row[k] * kPi / 180.0) + ";";
    }
    radians += text_util::FormatNumber(row[4]) + "\n";
  }
  const ReadTableResult read = ParseTable(radians, "data.csv");
  ExpectSameRows(read.table);
  EXPECT_TRUE(read.warnings.empty());  // the names said radians
}

TEST(TableInput, PercentUnitScalesTheValues) {
  const MeasurementTable table =
      ParseTable(
          "theta_i,phi_i,theta_o,phi_o,value [%]\n"
          "10,0,20,180,25\n45,90,60,-90,50\n70,0,30,0,12.5\n",
          "data.csv")
          .table;
  ExpectSameRows(table);
}

TEST(TableInput, UnknownOrContradictoryUnitsAreBadInput) {
  const std::string rows = kRows;
  EXPECT_NE(ParseError("theta_i [grad],phi_i,theta_o,phi_o,value\n" + rows)
                .find("data.csv:1:1: column 'theta_i': unknown unit 'grad'"),
            std::string::npos);
  EXPECT_NE(ParseError("# units: degrees\ntheta_i [rad],phi_i,theta_o,phi_o,"
                       "value\n" +
                       rows)
                .find("contradicts the 'units' metadata on line 1"),
            std::string::npos);
  EXPECT_NE(ParseError("theta_i,phi_i,theta_o,phi_o,value [W]\n" + rows)
                .find("column 'value': unknown unit 'w'"),
            std::string::npos);
  EXPECT_NE(ParseError("theta_i,phi_i,theta_o,phi_o,value,weight [%]\n"
                       "10,0,20,180,0.25,1\n")
                .find("column 'weight': takes no unit"),
            std::string::npos);
}

TEST(TableInput, TheFormatVersionIsCheckedWithOrWithoutAColon) {
  const std::string rows =
      std::string("theta_i,phi_i,theta_o,phi_o,value\n") + kRows;
  for (const char* line : {"# clothfit-table 2\n", "# clothfit-table: 2\n"}) {
    EXPECT_NE(ParseError(line + rows)
                  .find("unsupported table format version "
                        "'2'"),
              std::string::npos)
        << line;
  }
  ExpectSameRows(ParseTable("# clothfit-table: 1\n" + rows, "d.csv").table);
}

TEST(TableInput, UnknownColumnNamesTheClosestOne) {
  const std::string message =
      ParseError("theta_i,phi_i,theta_o,phi_o,vaule\n10,0,20,180,0.25\n");
  EXPECT_NE(message.find("data.csv:1:5: unknown column 'vaule' (did you mean "
                         "'value'?)"),
            std::string::npos)
      << message;
}

TEST(TableInput, RadiansReadAsDegreesAreWarnedAbout) {
  // Every angle <= 1.57 read as degrees: the warning, with or without a
  // units line saying degrees.
  const std::string rows =
      "0.17,0,0.35,3.14,0.25\n0.79,1.57,1.05,-1.57,0.5\n1.22,0,0.52,0,0.1\n";
  for (const std::string units : {"", "# units: degrees\n"}) {
    const ReadTableResult read = ParseTable(
        units + "theta_i,phi_i,theta_o,phi_o,value\n" + rows, "data.csv");
    ASSERT_EQ(read.warnings.size(), 1u);
    EXPECT_NE(read.warnings[0].find("data.csv: every angle is within the "
                                    "range of radians (largest theta 1.22"),
              std::string::npos)
        << read.warnings[0];
    EXPECT_NE(read.warnings[0].find("# units: radians"), std::string::npos);
  }
  // Read as radians: no warning; degrees beyond 1.6: none either.
  EXPECT_TRUE(ParseTable("# units: radians\ntheta_i,phi_i,theta_o,phi_o,"
                         "value\n" +
                             rows,
                         "data.csv")
                  .warnings.empty());
  EXPECT_TRUE(
      ParseTable(std::string("theta_i,phi_i,theta_o,phi_o,value\n") + kRows,
                 "data.csv")
          .warnings.empty());
}

TEST(TableInput, PercentValuesAreWarnedAbout) {
  const ReadTableResult read = ParseTable(
      "theta_i,phi_i,theta_o,phi_o,r,g,b\n"
      "10,0,20,180,25,30,20\n45,90,60,-90,50,40,60\n"
      "70,0,30,0,12.5,14,13\n",
      "data.csv");
  ASSERT_EQ(read.warnings.size(), 1u);
  EXPECT_NE(read.warnings[0].find("data.csv: the values look like percent "
                                  "(median 25, largest 50"),
            std::string::npos)
      << read.warnings[0];
  // A glossy table with a few bright rows is not percent, nor is one with
  // a value beyond 100.
  EXPECT_TRUE(ParseTable("theta_i,phi_i,theta_o,phi_o,value\n"
                         "10,0,10,180,40\n45,90,60,-90,0.5\n70,0,30,0,0.2\n",
                         "data.csv")
                  .warnings.empty());
  EXPECT_TRUE(ParseTable("theta_i,phi_i,theta_o,phi_o,value\n"
                         "10,0,10,180,400\n45,90,60,-90,5\n70,0,30,0,2\n",
                         "data.csv")
                  .warnings.empty());
}

TEST(TableInput, ArbitraryScaleIsRecognisedFromTheMetadata) {
  const std::string rows =
      std::string("theta_i,phi_i,theta_o,phi_o,value\n") + kRows;
  EXPECT_EQ(
      ArbitraryScaleNote(
          ParseTable("# sample: CUReT 44, arbitrary common scale\n" + rows,
                     "data.csv")
              .table),
      "sample: CUReT 44, arbitrary common scale");
  EXPECT_EQ(ArbitraryScaleNote(
                ParseTable("# scale: relative\n" + rows, "d.csv").table),
            "scale: relative");
  EXPECT_FALSE(ArbitraryScaleNote(
                   ParseTable("# sample: calibrated\n" + rows, "d.csv").table)
                   .has_value());
}

TEST(TableInput, WrittenAnglesReadAsTheyWereWritten) {
  // 60 degrees goes through a unit vector; it is written back as 60.
  MeasurementTable table =
      ParseTable("theta_i,phi_i,theta_o,phi_o,value\n60,30,70,-150,0.35\n",
                 "data.csv")
          .table;
  const std::string text = FormatTable(table);
  EXPECT_NE(text.find("\n60,30,70,-150,0.35\n"), std::string::npos) << text;
}

TEST(TextUtil, NumbersArePrintedInTheirShortestExactForm) {
  EXPECT_EQ(text_util::FormatNumber(0.35), "0.35");
  EXPECT_EQ(text_util::FormatNumber(60.0), "60");
  EXPECT_EQ(text_util::FormatNumber(1e-5), "1e-05");
  EXPECT_EQ(text_util::FormatNumber(0.1 + 0.2), "0.30000000000000004");
  const double x = 0.7 / 3.0;
  EXPECT_EQ(std::stod(text_util::FormatNumber(x)), x);
  EXPECT_EQ(text_util::FormatNumber(0.123456, 3), "0.123");
}

TEST(TextUtil, DidYouMeanNamesTheClosestCandidate) {
  using text_util::DidYouMean;
  EXPECT_EQ(DidYouMean("lobe", {"lobes", "lut", "out"}, "--"),
            " (did you mean '--lobes'?)");
  EXPECT_EQ(DidYouMean("lafourtune", {"thread", "cloth", "lafortune"}),
            " (did you mean 'lafortune'?)");
  EXPECT_EQ(DidYouMean("lienn", {"linen_plain", "velvet"}),
            "");  // 3 edits on 5 letters: too far, and no prefix
  EXPECT_EQ(DidYouMean("linen", {"linen_plain", "velvet", "silk_shot"}),
            " (did you mean 'linen_plain'?)");
  EXPECT_EQ(DidYouMean("silk", {"silk_shot", "silk_crepe_de_chine"}), "");
  EXPECT_EQ(DidYouMean("xyz", {"thread", "cloth"}), "");
  EXPECT_EQ(DidYouMean("clotth", {"thread", "cloth"}),
            " (did you mean 'cloth'?)");
}

}  // namespace
}  // namespace clothfit
