#include "io/table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <initializer_list>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_error.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

fs::path TestDir() { return testing_util::FreshTestDir("table_test_"); }

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// Parses `text` as "data.csv" and returns the InputError message ("" if the
// table was accepted).
std::string ParseError(const std::string& text,
                       const ReadTableOptions& options = {}) {
  try {
    ParseTable(text, "data.csv", options);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// Checks that parsing fails and the message holds every piece.
void ExpectError(const std::string& text,
                 std::initializer_list<const char*> pieces) {
  const std::string message = ParseError(text);
  ASSERT_FALSE(message.empty()) << "accepted:\n" << text;
  for (const char* piece : pieces) {
    EXPECT_NE(message.find(piece), std::string::npos)
        << "'" << piece << "' not in: " << message;
  }
}

void ExpectNear(const glm::dvec3& a, const glm::dvec3& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

const char kGoodTable[] =
    "# clothfit-table 1\n"
    "# quantity: brdf\n"
    "# units: degrees\n"
    "theta_i,phi_i,theta_o,phi_o,r,g,b\n"
    "0,0,0,0,1,2,3\n"
    "90,90,45,180,0.5,0.25,0.125\n";

TEST(TableTest, ReadsBasicTable) {
  const ReadTableResult result = ParseTable(kGoodTable, "data.csv");
  const MeasurementTable& table = result.table;
  EXPECT_EQ(result.skipped, 0);
  EXPECT_EQ(table.quantity, Quantity::kBrdf);
  EXPECT_EQ(table.channels, 3);
  EXPECT_EQ(table.direction_columns, DirectionColumns::kAngles);
  EXPECT_FALSE(table.has_sigma);
  EXPECT_FALSE(table.has_weight);
  EXPECT_FALSE(table.has_texels);
  ASSERT_EQ(table.rows.size(), 2u);
  ExpectNear(table.rows[0].wi, {0, 0, 1}, 1e-15);
  ExpectNear(table.rows[1].wi, {0, 1, 0}, 1e-15);
  const double h = std::sqrt(0.5);
  ExpectNear(table.rows[1].wo, {-h, 0, h}, 1e-15);
  EXPECT_EQ(table.rows[1].value, glm::dvec3(0.5, 0.25, 0.125));
  EXPECT_EQ(table.rows[0].source_line, 5);
  EXPECT_EQ(table.rows[1].source_line, 6);
  EXPECT_EQ(table.rows[0].sigma, glm::dvec3(1.0));
  EXPECT_EQ(table.rows[0].weight, 1.0);
  EXPECT_EQ(table.rows[0].s, -1);
}

TEST(TableTest, AcceptsAnyColumnOrderAndCase) {
  const ReadTableResult result = ParseTable(
      " B , Phi_O,THETA_I, g,theta_o ,R,phi_i\n3,180,90,2,45,1,90\n", "x.csv");
  ASSERT_EQ(result.table.rows.size(), 1u);
  const TableRow& row = result.table.rows[0];
  EXPECT_EQ(row.value, glm::dvec3(1, 2, 3));
  ExpectNear(row.wi, {0, 1, 0}, 1e-15);
  const double h = std::sqrt(0.5);
  ExpectNear(row.wo, {-h, 0, h}, 1e-15);
}

TEST(TableTest, KeepsUnknownMetadata) {
  const ReadTableResult result = ParseTable(
      "# clothfit-table 1\n# Sample : red velvet: back\n# just a comment\n"
      "#Quantity: Cosine_Weighted\n\n# units: radians\n"
      "theta_i,phi_i,theta_o,phi_o,value\n"
      "1.5707963267948966,0,3.141592653589793,-6.283185307179586,7\n",
      "data.csv");
  const MeasurementTable& table = result.table;
  EXPECT_EQ(table.quantity, Quantity::kCosineWeighted);
  EXPECT_EQ(table.Meta("sample"), "red velvet: back");
  EXPECT_EQ(table.Meta("SAMPLE"), "red velvet: back");
  EXPECT_EQ(table.Meta("quantity"), "Cosine_Weighted");
  EXPECT_FALSE(table.Meta("clothfit-table").has_value());
  EXPECT_FALSE(table.Meta("missing").has_value());
  ASSERT_EQ(table.metadata.size(), 3u);
  EXPECT_EQ(table.metadata[0].first, "sample");
  ASSERT_EQ(table.rows.size(), 1u);
  ExpectNear(table.rows[0].wi, {1, 0, 0}, 1e-15);
  ExpectNear(table.rows[0].wo, {0, 0, -1}, 1e-15);
}

TEST(TableTest, SetMetaReplacesOrAppends) {
  MeasurementTable table;
  table.SetMeta("Sample", "a");
  table.SetMeta("note", "b");
  table.SetMeta("SAMPLE", "c");
  ASSERT_EQ(table.metadata.size(), 2u);
  EXPECT_EQ(table.Meta("sample"), "c");
  EXPECT_EQ(table.metadata[1].second, "b");
}

TEST(TableTest, QuantityNames) {
  for (Quantity q :
       {Quantity::kBrdf, Quantity::kCosineWeighted, Quantity::kTransmittance}) {
    EXPECT_EQ(ParseQuantity(QuantityName(q)), q);
  }
  EXPECT_EQ(std::string(QuantityName(Quantity::kCosineWeighted)),
            "cosine_weighted");
  EXPECT_FALSE(ParseQuantity("btdf").has_value());
}

TEST(TableTest, NormalisesVectorColumns) {
  const ReadTableResult result = ParseTable(
      "wo_x,wo_y,wo_z,wi_x,wi_y,wi_z,value\n0,0,-2,3,0,4,1\n"
      "1e-300,0,0,0,1e300,1e300,1\n",
      "data.csv");
  const MeasurementTable& table = result.table;
  EXPECT_EQ(table.direction_columns, DirectionColumns::kVectors);
  EXPECT_EQ(table.channels, 1);
  ASSERT_EQ(table.rows.size(), 2u);
  ExpectNear(table.rows[0].wi, {0.6, 0, 0.8}, 1e-15);
  ExpectNear(table.rows[0].wo, {0, 0, -1}, 1e-15);
  ExpectNear(table.rows[1].wo, {1, 0, 0}, 1e-15);
  const double h = std::sqrt(0.5);
  ExpectNear(table.rows[1].wi, {0, h, h}, 1e-15);
}

TEST(TableTest, OneChannelFillsAllComponents) {
  const ReadTableResult result = ParseTable(
      "theta_i,phi_i,theta_o,phi_o,value,sigma\n10,20,30,40,0.5,0.1\n",
      "data.csv");
  EXPECT_EQ(result.table.channels, 1);
  EXPECT_TRUE(result.table.has_sigma);
  EXPECT_EQ(result.table.rows[0].value, glm::dvec3(0.5));
  EXPECT_EQ(result.table.rows[0].sigma, glm::dvec3(0.1));
}

TEST(TableTest, ReadsSigmaWeightAndTexels) {
  const ReadTableResult result = ParseTable(
      "theta_i,phi_i,theta_o,phi_o,r,g,b,sigma_r,sigma_g,sigma_b,weight,s,t\n"
      "10,20,30,40,1,2,3,0.1,0.2,0.3,0,4,5\n"
      "10,20,30,40,1,2,3,0.1,0.2,0.3,2.5,0,7.0\n",
      "data.csv");
  const MeasurementTable& table = result.table;
  EXPECT_TRUE(table.has_sigma);
  EXPECT_TRUE(table.has_weight);
  EXPECT_TRUE(table.has_texels);
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.rows[0].sigma, glm::dvec3(0.1, 0.2, 0.3));
  EXPECT_EQ(table.rows[0].weight, 0.0);
  EXPECT_EQ(table.rows[0].s, 4);
  EXPECT_EQ(table.rows[0].t, 5);
  EXPECT_EQ(table.rows[1].weight, 2.5);
  EXPECT_EQ(table.rows[1].s, 0);
  EXPECT_EQ(table.rows[1].t, 7);
}

TEST(TableTest, ReadsAlpha) {
  const ReadTableResult result = ParseTable(
      "theta_i,phi_i,theta_o,phi_o,Alpha,value\n1,2,3,4,0,5\n1,2,3,4,1,5\n"
      "1,2,3,4,0.25,5\n",
      "data.csv");
  const MeasurementTable& table = result.table;
  EXPECT_TRUE(table.has_alpha);
  ASSERT_EQ(table.rows.size(), 3u);
  EXPECT_EQ(table.rows[0].alpha, 0.0);
  EXPECT_EQ(table.rows[1].alpha, 1.0);
  EXPECT_EQ(table.rows[2].alpha, 0.25);
  EXPECT_EQ(table.rows[2].value, glm::dvec3(5));

  const ReadTableResult without = ParseTable(kGoodTable, "data.csv");
  EXPECT_FALSE(without.table.has_alpha);
  EXPECT_EQ(without.table.rows[0].alpha, 1.0);
}

TEST(TableTest, SingleSigmaAppliesToAllChannels) {
  const ReadTableResult result = ParseTable(
      "theta_i,phi_i,theta_o,phi_o,r,g,b,sigma\n1,2,3,4,1,2,3,0.5\n", "d.csv");
  EXPECT_EQ(result.table.rows[0].sigma, glm::dvec3(0.5));
}

TEST(TableTest, TransmittanceNeedsOnlyOutgoingDirection) {
  const ReadTableResult result =
      ParseTable("# quantity: transmittance\ntheta_o,phi_o,value\n180,0,0.25\n",
                 "data.csv");
  const MeasurementTable& table = result.table;
  EXPECT_EQ(table.quantity, Quantity::kTransmittance);
  ASSERT_EQ(table.rows.size(), 1u);
  EXPECT_EQ(table.rows[0].wi, glm::dvec3(0, 0, 1));
  ExpectNear(table.rows[0].wo, {0, 0, -1}, 1e-15);

  const ReadTableResult with_incident = ParseTable(
      "# quantity: transmittance\ntheta_i,phi_i,theta_o,phi_o,value\n"
      "90,0,180,0,0.25\n",
      "data.csv");
  ExpectNear(with_incident.table.rows[0].wi, {1, 0, 0}, 1e-15);

  const ReadTableResult vectors = ParseTable(
      "# quantity: transmittance\nwo_x,wo_y,wo_z,value\n0,0,-3,0.25\n",
      "data.csv");
  EXPECT_EQ(vectors.table.rows[0].wi, glm::dvec3(0, 0, 1));
  ExpectNear(vectors.table.rows[0].wo, {0, 0, -1}, 1e-15);
}

TEST(TableTest, AcceptsCrLfAndBlankLines) {
  const ReadTableResult result = ParseTable(
      "\xEF\xBB\xBF# quantity: brdf\r\n\r\n  \r\ntheta_i,phi_i,theta_o,phi_o,"
      "value\r\n\r\n1,2,3,4,5\r\n# commented-out row\r\n6,7,8,9,10\r\n",
      "data.csv");
  ASSERT_EQ(result.table.rows.size(), 2u);
  EXPECT_EQ(result.table.rows[0].value, glm::dvec3(5));
  EXPECT_EQ(result.table.rows[0].source_line, 6);
  EXPECT_EQ(result.table.rows[1].value, glm::dvec3(10));
  EXPECT_EQ(result.table.rows[1].source_line, 8);
}

// One test per error class.

TEST(TableErrorTest, MissingColumn) {
  ExpectError("# x: y\ntheta_i,phi_i,theta_o,r,g,b\n1,2,3,4,5,6\n",
              {"data.csv:2:", "'phi_o'", "missing"});
  ExpectError("theta_i,phi_i,theta_o,phi_o\n1,2,3,4\n",
              {"data.csv:1:", "'value'", "missing"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,b\n1,2,3,4,5,6\n",
              {"data.csv:1:", "'g'", "missing"});
  ExpectError("wi_x,wi_y,wi_z,wo_x,wo_z,value\n1,2,3,4,5,6\n",
              {"data.csv:1:", "'wo_y'", "missing"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,s\n1,2,3,4,5,6\n",
              {"data.csv:1:", "'t'", "missing"});
  ExpectError(
      "# quantity: transmittance\ntheta_i,theta_o,phi_o,value\n1,2,3,4\n",
      {"data.csv:2:", "'phi_i'", "missing"});
}

TEST(TableErrorTest, DuplicateColumn) {
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b,THETA_I\n1,2,3,4,5,6,7,8\n",
              {"data.csv:1:8:", "'theta_i'", "duplicate"});
}

TEST(TableErrorTest, UnknownColumn) {
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b,beta\n1,2,3,4,5,6,7,8\n",
              {"data.csv:1:8:", "'beta'", "unknown"});
  ExpectError("theta_i,,theta_o,phi_o,r,g,b\n1,2,3,4,5,6,7\n",
              {"data.csv:1:2:", "empty column name"});
}

TEST(TableErrorTest, AnglesAndVectorsMixed) {
  ExpectError(
      "theta_i,phi_i,theta_o,phi_o,wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,value\n"
      "1,2,3,4,5,6,7,8,9,10,11\n",
      {"data.csv:1:5:", "'wi_x'", "mixed"});
}

TEST(TableErrorTest, ValueMixedWithRgb) {
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,r,g,b\n1,2,3,4,5,6,7,8\n",
              {"data.csv:1:6:", "'r'", "mixed"});
  ExpectError(
      "theta_i,phi_i,theta_o,phi_o,r,g,b,sigma,sigma_g\n1,2,3,4,5,6,7,8,9\n",
      {"data.csv:1:9:", "'sigma_g'", "mixed"});
}

TEST(TableErrorTest, UnparsableNumber) {
  ExpectError(
      "# units: degrees\n\n# a: b\n\n\ntheta_i,phi_i,theta_o,phi_o,r\n"
      "1,2,3,4\n",
      {"data.csv:6:", "'g'", "missing"});
  ExpectError(
      "# units: degrees\n\n# a: b\n\n\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n"
      "1,2,abc,4,5,6,7\n",
      {"data.csv:7:3:", "column 'theta_o'", "cannot parse 'abc' as a number"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,2,3,4,5,6,7x\n",
              {"data.csv:2:7:", "'b'", "cannot parse"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,2,3, ,5,6,7\n",
              {"data.csv:2:4:", "'phi_o'", "empty"});
}

TEST(TableErrorTest, NotFinite) {
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,2,3,4,nan,6,7\n",
              {"data.csv:2:5:", "'r'", "finite"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,2,3,4,5,-inf,7\n",
              {"data.csv:2:6:", "'g'", "finite"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,2,3,4,5,6,1e999\n",
              {"data.csv:2:7:", "'b'", "finite"});
}

TEST(TableErrorTest, AngleOutOfRange) {
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,2,181,4,5,6,7\n",
              {"data.csv:2:3:", "'theta_o'", "out of range"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b\n-1,2,3,4,5,6,7\n",
              {"data.csv:2:1:", "'theta_i'", "out of range"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,-361,3,4,5,6,7\n",
              {"data.csv:2:2:", "'phi_i'", "out of range"});
  ExpectError(
      "# units: radians\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n"
      "1,2,3.2,4,5,6,7\n",
      {"data.csv:3:3:", "'theta_o'", "out of range", "radians"});
  EXPECT_EQ(ParseError("theta_i,phi_i,theta_o,phi_o,r,g,b\n"
                       "0,-360,180,360,5,6,7\n"),
            "");
}

TEST(TableErrorTest, ZeroDirectionVector) {
  ExpectError("wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,value\n0,0,1,0,0,0,1\n",
              {"data.csv:2:4:", "'wo_x'", "zero"});
  ExpectError("wo_x,wo_y,wo_z,value,wi_z,wi_y,wi_x\n0,0,1,1,0,-0,0\n",
              {"data.csv:2:7:", "'wi_x'", "zero"});
}

TEST(TableErrorTest, NonPositiveSigma) {
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,sigma\n1,2,3,4,5,-1\n",
              {"data.csv:2:6:", "'sigma'", "positive"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,sigma\n1,2,3,4,5,0\n",
              {"data.csv:2:6:", "'sigma'", "positive"});
  ExpectError(
      "theta_i,phi_i,theta_o,phi_o,r,g,b,sigma_r,sigma_g,sigma_b\n"
      "1,2,3,4,5,6,7,1,-2,3\n",
      {"data.csv:2:9:", "'sigma_g'", "positive"});
  ExpectError(
      "theta_i,phi_i,theta_o,phi_o,value,sigma_r,sigma_g,sigma_b\n"
      "1,2,3,4,5,1,2,3\n",
      {"data.csv:1:6:", "'sigma_r'", "r,g,b"});
}

TEST(TableErrorTest, NegativeWeight) {
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,weight\n1,2,3,4,5,-0.5\n",
              {"data.csv:2:6:", "'weight'", "non-negative"});
}

// Fields whose squared normalised residual could overflow a fit's cost.
TEST(TableErrorTest, HugeValuesSigmasAndWeights) {
  ExpectError("theta_i,phi_i,theta_o,phi_o,value\n1,2,3,4,1e300\n",
              {"data.csv:2:5:", "'value'", "out of range"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,2,3,4,1,-2e31,1\n",
              {"data.csv:2:6:", "'g'", "out of range"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,sigma\n1,2,3,4,5,1e-40\n",
              {"data.csv:2:6:", "'sigma'", "out of range"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,sigma\n1,2,3,4,5,1e31\n",
              {"data.csv:2:6:", "'sigma'", "out of range"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,weight\n1,2,3,4,5,1e31\n",
              {"data.csv:2:6:", "'weight'", "out of range"});
  // The limits themselves are accepted.
  EXPECT_EQ(ParseError("theta_i,phi_i,theta_o,phi_o,value,sigma,weight\n"
                       "1,2,3,4,-1e30,1e-30,1e30\n"),
            "");
}

TEST(TableErrorTest, AlphaOutOfRange) {
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,alpha\n1,2,3,4,5,1.5\n",
              {"data.csv:2:6:", "column 'alpha': must be in [0, 1]"});
  ExpectError("alpha,theta_i,phi_i,theta_o,phi_o,value\n-0.01,1,2,3,4,5\n",
              {"data.csv:2:1:", "column 'alpha': must be in [0, 1]"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,alpha\n1,2,3,4,5,nan\n",
              {"data.csv:2:6:", "'alpha'", "finite"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,alpha,ALPHA\n1,2,3,4,5,1,1\n",
              {"data.csv:1:7:", "duplicate column 'alpha'"});
}

TEST(TableErrorTest, BadTexelIndex) {
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,s,t\n1,2,3,4,5,1.5,2\n",
              {"data.csv:2:6:", "'s'", "integer"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,t,s\n1,2,3,4,5,-1,2\n",
              {"data.csv:2:6:", "'t'", "integer"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,value,s,t\n1,2,3,4,5,1e10,2\n",
              {"data.csv:2:6:", "'s'", "integer"});
}

TEST(TableErrorTest, WrongFieldCount) {
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,2,3,4,5\n",
              {"data.csv:2:6:", "'g'", "fields"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,r,g,b\n1,2,3,4,5,6,7,8\n",
              {"data.csv:2:8:", "8 fields", "header has 7"});
}

TEST(TableErrorTest, BadMetadata) {
  ExpectError(
      "# clothfit-table 1\n# quantity: btdf\ntheta_o,phi_o,value\n1,2,3\n",
      {"data.csv:2:", "quantity", "'btdf'"});
  ExpectError(
      "# units: gradians\ntheta_i,phi_i,theta_o,phi_o,value\n1,2,3,4,5\n",
      {"data.csv:1:", "units", "'gradians'"});
}

// "# clothfit-table N": version 1 is read (any case); another version, or
// none, is refused rather than read as if it were 1.
TEST(TableErrorTest, FormatVersionOtherThanOne) {
  const std::string rest = "theta_i,phi_i,theta_o,phi_o,value\n1,2,3,4,5\n";
  ExpectError("# clothfit-table 2\n" + rest,
              {"data.csv:1:", "version '2'", "clothfit-table 1"});
  ExpectError("# quantity: brdf\n#clothfit-table\n" + rest,
              {"data.csv:2:", "version ''"});
  EXPECT_EQ(ParseError("# CLOTHFIT-TABLE 1\n" + rest), "");
  // Other words are comments.
  EXPECT_EQ(ParseError("# clothfit-tables 2\n# clothfit table 2\n" + rest), "");
}

TEST(TableErrorTest, EmptyTable) {
  ExpectError("# quantity: brdf\n\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n\n",
              {"data.csv:3:", "no rows"});
  ExpectError("# clothfit-table 1\n# quantity: brdf\n\n",
              {"data.csv", "no header"});
  ExpectError("", {"data.csv", "no header"});
}

TEST(TableErrorTest, MissingFile) {
  const fs::path path = TestDir() / "absent.csv";
  try {
    ReadTable(path.string());
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find("cannot read"), std::string::npos) << message;
  }
}

TEST(TableErrorTest, ReadingDirectoryFails) {
  const fs::path dir = TestDir();
  try {
    ReadTable(dir.string());
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(dir.string() + ": cannot read"), std::string::npos)
        << message;
  }
  EXPECT_THROW(ReadFileToString(dir.string()), InputError);
}

TEST(TableTest, ReadTableNamesFileInErrors) {
  const fs::path path = TestDir() / "bad.csv";
  WriteText(path, "theta_i,phi_i,theta_o,phi_o,value\n1,2,3,x,5\n");
  try {
    ReadTable(path.string());
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(
        std::string(error.what()),
        path.string() + ":2:4: column 'phi_o': cannot parse 'x' as a number");
  }
}

TEST(TableTest, SkipInvalidCountsDroppedRows) {
  const std::string text =
      "theta_i,phi_i,theta_o,phi_o,value,sigma\n"
      "1,2,3,4,5,1\n"
      "1,2,abc,4,5,1\n"
      "1,2,3,4,nan,1\n"
      "1,2,3,4,5,-1\n"
      "1,2,3,4\n"
      "1,2,200,4,5,1\n"
      "6,7,8,9,10,1\n";
  ReadTableOptions options;
  options.skip_invalid = true;
  const ReadTableResult result = ParseTable(text, "data.csv", options);
  EXPECT_EQ(result.skipped, 5);
  EXPECT_EQ(result.first_skip_reason,
            "data.csv:3:3: column 'theta_o': cannot parse 'abc' as a number");
  ASSERT_EQ(result.table.rows.size(), 2u);
  EXPECT_EQ(result.table.rows[0].source_line, 2);
  EXPECT_EQ(result.table.rows[1].source_line, 8);

  // Without the option the first bad row is an error.
  EXPECT_NE(ParseError(text).find("data.csv:3:3:"), std::string::npos);
}

TEST(TableTest, SkipInvalidKeepsHeaderErrorsAndEmptyTables) {
  ReadTableOptions options;
  options.skip_invalid = true;
  EXPECT_NE(ParseError("theta_i,phi_i,theta_o,value\n1,2,3,4\n", options)
                .find("missing column 'phi_o'"),
            std::string::npos);
  const std::string message = ParseError(
      "theta_i,phi_i,theta_o,phi_o,value\n1,2,3,4,x\n1,2,3,4\n", options);
  EXPECT_NE(message.find("data.csv:1: table has no rows"), std::string::npos)
      << message;
  EXPECT_NE(message.find("2 rows"), std::string::npos) << message;
}

TEST(TableTest, SurvivesArbitraryBytes) {
  std::string junk = "theta_i,phi_i,theta_o,phi_o,value\n";
  junk += std::string("1,2,3,4,\0\xff\xfe", 11) + "\n";
  junk += std::string(100000, 'x') + "\n";
  junk += std::string(5000, ',') + "\n";
  ReadTableOptions options;
  options.skip_invalid = true;
  const std::string message = ParseError(junk, options);
  EXPECT_NE(message.find("no rows"), std::string::npos);
  const std::string strict = ParseError(junk);
  EXPECT_NE(strict.find("data.csv:2:5: column 'value': cannot parse "
                        "'\\x00\\xff\\xfe'"),
            std::string::npos)
      << strict;
  for (int seed = 0; seed < 200; ++seed) {
    std::string bytes;
    unsigned state = 12345u + static_cast<unsigned>(seed);
    for (int i = 0; i < 300; ++i) {
      state = state * 1103515245u + 12345u;
      bytes += static_cast<char>(state >> 16);
    }
    ParseError(std::string(kGoodTable) + bytes);
    ParseError(bytes);
  }
}

MeasurementTable SampleTable(DirectionColumns columns) {
  MeasurementTable table;
  table.quantity = Quantity::kCosineWeighted;
  table.direction_columns = columns;
  table.has_sigma = true;
  table.has_weight = true;
  table.has_texels = true;
  table.SetMeta("sample", "linen, plain weave");
  table.SetMeta("units", "radians");  // Superseded by the writer's units.
  for (int i = 0; i < 50; ++i) {
    TableRow row;
    row.wi = glm::normalize(glm::dvec3(std::sin(i * 1.1), std::cos(i * 0.7),
                                       1.05 + std::sin(i * 0.3)));
    row.wo = glm::normalize(
        glm::dvec3(std::cos(i * 1.3), std::sin(i * 0.9), std::cos(i * 0.5)));
    row.value = glm::dvec3(1.0 / (i + 3), 0.1 * i, -1e-300 * i);
    row.sigma = glm::dvec3(0.1 + i, 1e-20, 3.0);
    row.weight = 0.5 * i;
    row.s = i % 7;
    row.t = i / 7;
    table.rows.push_back(row);
  }
  table.rows[0].wi = glm::dvec3(0, 0, 1);
  table.rows[1].wo = glm::dvec3(std::sin(1e-9), 0, std::cos(1e-9));
  return table;
}

void ExpectSameTable(const MeasurementTable& a, const MeasurementTable& b) {
  EXPECT_EQ(a.quantity, b.quantity);
  EXPECT_EQ(a.channels, b.channels);
  EXPECT_EQ(a.direction_columns, b.direction_columns);
  EXPECT_EQ(a.has_sigma, b.has_sigma);
  EXPECT_EQ(a.has_weight, b.has_weight);
  EXPECT_EQ(a.has_texels, b.has_texels);
  EXPECT_EQ(a.has_alpha, b.has_alpha);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (size_t i = 0; i < a.rows.size(); ++i) {
    ExpectNear(a.rows[i].wi, b.rows[i].wi, 2e-15);
    ExpectNear(a.rows[i].wo, b.rows[i].wo, 2e-15);
    if (a.channels == 1) {
      EXPECT_EQ(a.rows[i].value, glm::dvec3(b.rows[i].value.x));
      EXPECT_EQ(a.rows[i].sigma, glm::dvec3(b.rows[i].sigma.x));
    } else {
      EXPECT_EQ(a.rows[i].value, b.rows[i].value);
      EXPECT_EQ(a.rows[i].sigma, b.rows[i].sigma);
    }
    EXPECT_EQ(a.rows[i].weight, b.rows[i].weight);
    EXPECT_EQ(a.rows[i].s, b.rows[i].s);
    EXPECT_EQ(a.rows[i].t, b.rows[i].t);
  }
}

// A file is read piece by piece (1 MiB): lines split across pieces, CRLF
// endings and a missing final newline read as from one string, and a bad
// row past the first piece is named by its line.
TEST(TableTest, ReadingInPiecesEqualsParsingTheWholeText) {
  std::string text =
      "# quantity: cosine_weighted\r\nwi_x,wi_y,wi_z,wo_x,wo_y,"
      "wo_z,r,g,b,s,t\r\n";
  int rows = 0;
  while (text.size() < 2500000) {
    const double x = 0.001 * (rows % 997);
    text += std::to_string(x) + ",0.25,0.9," + std::to_string(-x) +
            ",0.125,0.8,1.5,2.5," + std::to_string(rows) + "," +
            std::to_string(rows % 7) + ",3\r\n";
    ++rows;
  }
  text += "0.5,0.5,0.5,0.1,0.2,0.3,1,2,3,4,5";  // no final newline
  ++rows;
  const fs::path path = TestDir() / "big.csv";
  WriteText(path, text);
  const MeasurementTable read = ReadTable(path.string()).table;
  ASSERT_EQ(read.rows.size(), static_cast<size_t>(rows));
  ExpectSameTable(read, ParseTable(text, "mem").table);
  EXPECT_EQ(read.rows.back().source_line, rows + 2);

  WriteText(path, text + "\n0.5,0.5,0.5,0.1,0.2,0.3,1,2,oops,4,5\n");
  try {
    ReadTable(path.string());
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what())
                  .find(path.string() + ":" + std::to_string(rows + 3) + ":9:"),
              std::string::npos)
        << error.what();
  }
}

TEST(TableTest, NumbersAsStrtodSpellsThem) {
  const MeasurementTable t =
      ParseTable("theta_i,phi_i,theta_o,phi_o,value\n+1.5,2,3e0,4,1e-320\n",
                 "data.csv")
          .table;
  EXPECT_NEAR(t.rows[0].wi.z, std::cos(1.5 * kPi / 180.0), 1e-15);
  EXPECT_GT(t.rows[0].value.x, 0.0);  // subnormal, kept
  EXPECT_LT(t.rows[0].value.x, 1e-300);
  ExpectError("theta_i,phi_i,theta_o,phi_o,value\n1,2,3,4,1e999\n",
              {"data.csv:2:5:", "not a finite number"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,value\n1,2,3,4,++1\n",
              {"data.csv:2:5:", "cannot parse"});
  ExpectError("theta_i,phi_i,theta_o,phi_o,value\n1,2,3,4,banana\n",
              {"data.csv:2:5:", "cannot parse"});
}

// A table of many megabytes is written in pieces; the file is the text
// FormatTable makes, and reads back row for row.
TEST(TableTest, ALargeTableIsWrittenWholeInPieces) {
  MeasurementTable table = SampleTable(DirectionColumns::kAngles);
  const TableRow first = table.rows[0];
  table.rows.assign(100000, first);
  for (size_t i = 0; i < table.rows.size(); ++i) {
    table.rows[i].value.x = 0.001 * static_cast<double>(i);
  }
  const fs::path path = TestDir() / "large.csv";
  WriteTable(table, path.string());
  const std::string text = ReadFileToString(path.string());
  EXPECT_GT(text.size(), 3u << 20);  // several pieces of ~1 MiB
  EXPECT_EQ(text, FormatTable(table));
  const MeasurementTable back = ReadTable(path.string()).table;
  ASSERT_EQ(back.rows.size(), table.rows.size());
  EXPECT_EQ(back.rows.back().value.x, table.rows.back().value.x);
}

TEST(TableTest, RoundTripAngles) {
  const MeasurementTable table = SampleTable(DirectionColumns::kAngles);
  const fs::path path = TestDir() / "angles.csv";
  WriteTable(table, path.string());
  const std::string text = ReadFileToString(path.string());
  EXPECT_EQ(text.rfind("# clothfit-table 1\n# quantity: cosine_weighted\n"
                       "# units: degrees\n# sample: linen, plain weave\n"
                       "theta_i,phi_i,theta_o,phi_o,r,g,b,sigma_r,sigma_g,"
                       "sigma_b,weight,s,t\n",
                       0),
            0u)
      << text;
  const ReadTableResult result = ReadTable(path.string());
  ExpectSameTable(result.table, table);
  EXPECT_EQ(result.table.Meta("sample"), "linen, plain weave");
  EXPECT_EQ(result.table.Meta("units"), "degrees");
}

TEST(TableTest, RoundTripVectorsOneChannel) {
  MeasurementTable table = SampleTable(DirectionColumns::kVectors);
  table.channels = 1;
  for (TableRow& row : table.rows) {
    row.value = glm::dvec3(row.value.x);
    row.sigma = glm::dvec3(row.sigma.x);
  }
  const std::string text = FormatTable(table);
  EXPECT_NE(
      text.find("\nwi_x,wi_y,wi_z,wo_x,wo_y,wo_z,value,sigma,weight,s,t\n"),
      std::string::npos)
      << text;
  ExpectSameTable(ParseTable(text, "mem").table, table);
}

TEST(TableTest, RoundTripAlpha) {
  MeasurementTable table = SampleTable(DirectionColumns::kAngles);
  table.has_alpha = true;
  for (size_t i = 0; i < table.rows.size(); ++i) {
    table.rows[i].alpha = static_cast<double>(i) / 49.0;
  }
  const std::string text = FormatTable(table);
  EXPECT_NE(text.find("\ntheta_i,phi_i,theta_o,phi_o,r,g,b,sigma_r,sigma_g,"
                      "sigma_b,weight,alpha,s,t\n"),
            std::string::npos)
      << text;
  const MeasurementTable back = ParseTable(text, "mem").table;
  ExpectSameTable(back, table);
  EXPECT_TRUE(back.has_alpha);
  for (size_t i = 0; i < table.rows.size(); ++i) {
    EXPECT_EQ(back.rows[i].alpha, table.rows[i].alpha);
  }

  // Without has_alpha the column is not written.
  table.has_alpha = false;
  EXPECT_EQ(FormatTable(table).find("alpha"), std::string::npos);
}

TEST(TableTest, NormalColumnsAreReadNormalisedAndRoundTrip) {
  const ReadTableResult result = ParseTable(
      "theta_i,phi_i,theta_o,phi_o,value,normal_x,normal_y,normal_z\n"
      "1,2,3,4,5,0,0,2\n1,2,3,4,5,0.3,0,0.4\n",
      "data.csv");
  const MeasurementTable& table = result.table;
  EXPECT_TRUE(table.has_normal);
  EXPECT_EQ(table.rows[0].normal, glm::dvec3(0, 0, 1));
  EXPECT_NEAR(glm::length(table.rows[1].normal - glm::dvec3(0.6, 0, 0.8)), 0.0,
              1e-15);
  const MeasurementTable back = ParseTable(FormatTable(table), "mem").table;
  EXPECT_TRUE(back.has_normal);
  EXPECT_NEAR(glm::length(back.rows[1].normal - table.rows[1].normal), 0.0,
              1e-15);
  EXPECT_FALSE(ParseTable(kGoodTable, "data.csv").table.has_normal);
}

TEST(TableErrorTest, NormalColumnsIncompleteOrZero) {
  ExpectError(
      "theta_i,phi_i,theta_o,phi_o,value,normal_x,normal_z\n"
      "1,2,3,4,5,0,1\n",
      {"data.csv:1:", "missing column 'normal_y'"});
  ExpectError(
      "theta_i,phi_i,theta_o,phi_o,value,normal_x,normal_y,normal_z\n"
      "1,2,3,4,5,0,0,0\n",
      {"data.csv:2:6:", "zero vector"});
}

TEST(TableTest, RoundTripTransmittance) {
  MeasurementTable table;
  table.quantity = Quantity::kTransmittance;
  table.channels = 1;
  TableRow row;
  row.wo = DirectionFromAngles(2.5, -0.5);
  row.value = glm::dvec3(0.125);
  table.rows.push_back(row);
  const std::string text = FormatTable(table);
  EXPECT_NE(text.find("\ntheta_o,phi_o,value\n"), std::string::npos) << text;
  ExpectSameTable(ParseTable(text, "mem").table, table);

  // A non-default incident direction is not dropped.
  table.rows[0].wi = DirectionFromAngles(0.5, 1.0);
  const std::string with_incident = FormatTable(table);
  EXPECT_NE(with_incident.find("\ntheta_i,phi_i,theta_o,phi_o,value\n"),
            std::string::npos);
  ExpectSameTable(ParseTable(with_incident, "mem").table, table);
}

TEST(TableTest, AnglesAndDirections) {
  ExpectNear(DirectionFromAngles(kPi / 2, kPi / 2), {0, 1, 0}, 1e-15);
  for (double theta : {0.0, 1e-9, 0.3, kPi / 2, 2.0, kPi}) {
    for (double phi : {-3.0, -1e-3, 0.0, 1.0, 3.1}) {
      const glm::dvec3 w = DirectionFromAngles(theta, phi);
      double t = 0.0;
      double p = 0.0;
      AnglesFromDirection(w, &t, &p);
      ExpectNear(DirectionFromAngles(t, p), w, 1e-15);
      EXPECT_NEAR(t, theta, 1e-15);
      if (theta > 0.0 && theta < kPi) {
        EXPECT_NEAR(p, phi, 1e-13);
      }
    }
  }
}

TEST(AtomicFileTest, WritesWithoutLeavingTempFiles) {
  const fs::path dir = TestDir();
  const fs::path path = dir / "out.txt";
  WriteFileAtomically(path.string(), "first");
  WriteFileAtomically(path.string(), "second\n");
  EXPECT_EQ(ReadFileToString(path.string()), "second\n");
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    (void)entry;
    ++entries;
  }
  EXPECT_EQ(entries, 1);
}

TEST(AtomicFileTest, ThrowsOnUnwritablePath) {
  const fs::path dir = TestDir();
  const fs::path path = dir / "no_such_dir" / "out.csv";
  try {
    WriteFileAtomically(path.string(), "x");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              path.string() + ": cannot write: No such file or directory");
  }
  EXPECT_THROW(
      WriteTable(SampleTable(DirectionColumns::kAngles), path.string()),
      InputError);

  // A directory in the way of the rename: the old directory stays and no
  // temporary file is left behind.
  fs::create_directories(dir / "taken");
  EXPECT_THROW(WriteFileAtomically((dir / "taken").string(), "x"), InputError);
  EXPECT_TRUE(fs::is_directory(dir / "taken"));
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    (void)entry;
    ++entries;
  }
  EXPECT_EQ(entries, 1);
}

TEST(InputErrorTest, FormatLocation) {
  EXPECT_EQ(FormatLocation("a.csv", 3, 7), "a.csv:3:7");
  EXPECT_EQ(FormatLocation("a.csv", 3, 0), "a.csv:3");
  EXPECT_EQ(FormatLocation("a.csv", 0, 0), "a.csv");
}

}  // namespace
}  // namespace clothfit

namespace clothfit {
namespace {

TEST(ReadTable, DirectionsOnlyWhenValuesOptional) {
  const std::string text = "theta_i,phi_i,theta_o,phi_o\n10,0,20,180\n";
  EXPECT_THROW(ParseTable(text, "dirs.csv"), InputError);
  ReadTableOptions options;
  options.values_optional = true;
  const MeasurementTable t = ParseTable(text, "dirs.csv", options).table;
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.channels, 3);
  EXPECT_EQ(t.rows[0].value, glm::dvec3(0.0));
  EXPECT_NEAR(t.rows[0].wo.x, -std::sin(20 * 3.14159265358979323846 / 180),
              1e-15);
}

// A row sink sees every valid row in file order, the table keeps none, and
// what the sink throws is its own error, not a row to skip.
TEST(TableTest, RowSinkGetsTheValidRowsInOrderAndTheTableKeepsNone) {
  const fs::path dir = testing_util::FreshTestDir("table_");
  const fs::path path = dir / "t.csv";
  WriteText(path,
            "# quantity: brdf\n"
            "theta_i,phi_i,theta_o,phi_o,value\n"
            "10,0,20,180,0.5\n"
            "10,0,25,180,x\n"  // not a number
            "30,0,40,90,0.25\n");
  ReadTableOptions options;
  options.skip_invalid = true;
  std::vector<TableRow> seen;
  options.row_sink = [&](const MeasurementTable& table, const TableRow& row) {
    EXPECT_EQ(table.channels, 1);  // the header, before the rows
    EXPECT_TRUE(table.rows.empty());
    seen.push_back(row);
  };
  const ReadTableResult streamed = ReadTable(path.string(), options);
  EXPECT_TRUE(streamed.table.rows.empty());
  EXPECT_EQ(streamed.skipped, 1);
  EXPECT_EQ(streamed.table.source, path.string());
  options.row_sink = nullptr;
  const ReadTableResult held = ReadTable(path.string(), options);
  ASSERT_EQ(held.table.rows.size(), 2u);
  ASSERT_EQ(seen.size(), 2u);
  for (size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(seen[i].wi, held.table.rows[i].wi);
    EXPECT_EQ(seen[i].wo, held.table.rows[i].wo);
    EXPECT_EQ(seen[i].value, held.table.rows[i].value);
    EXPECT_EQ(seen[i].source_line, held.table.rows[i].source_line);
  }
  EXPECT_EQ(seen[1].source_line, 5);

  options.row_sink = [](const MeasurementTable&, const TableRow& row) {
    if (row.source_line == 5) throw InputError("sink: refused");
  };
  EXPECT_EQ(testing_util::ErrorOf([&] { ReadTable(path.string(), options); }),
            "sink: refused");
}

// The header alone: columns and metadata, read no further than the header
// line (the bad row after it is not seen); a file without one is refused.
TEST(TableTest, ReadTableHeaderStopsAtTheHeader) {
  const fs::path dir = testing_util::FreshTestDir("table_");
  const fs::path path = dir / "t.csv";
  WriteText(path,
            "# quantity: cosine_weighted\n"
            "# lab: ours\n"
            "theta_i,phi_i,theta_o,phi_o,r,g,b,sigma,s,t\n"
            "10,0,20,180,not a number,0.5,0.5,0.1,0,0\n");
  const MeasurementTable header = ReadTableHeader(path.string());
  EXPECT_TRUE(header.rows.empty());
  EXPECT_EQ(header.quantity, Quantity::kCosineWeighted);
  EXPECT_EQ(header.channels, 3);
  EXPECT_TRUE(header.has_sigma);
  EXPECT_TRUE(header.has_texels);
  EXPECT_FALSE(header.has_alpha);
  EXPECT_EQ(header.Meta("lab").value_or(""), "ours");
  EXPECT_EQ(header.source, path.string());

  WriteText(path, "# quantity: brdf\n# only metadata\n");
  testing_util::ExpectHas(
      testing_util::ErrorOf([&] { ReadTableHeader(path.string()); }),
      {path.string(), "no header"});
}

}  // namespace
}  // namespace clothfit
