// SPDX-License-Identifier: GPL-3.0-or-later
// The EPW reader (shadow/weather.hpp): the header, the hour-ending convention, leap years,
// missing values and one error naming file, line and field for a bad file.
#include <shadow/error.hpp>
#include <shadow/sun.hpp>
#include <shadow/epw.hpp>
#include <shadow/weather.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

namespace {

const char* kHeader =
    "LOCATION,Testville,XX,ZZZ,Test,000001,49.5,8.5,1.0,96.0\n"
    "DESIGN CONDITIONS,0\n"
    "TYPICAL/EXTREME PERIODS,0\n"
    "GROUND TEMPERATURES,0\n"
    "HOLIDAYS/DAYLIGHT SAVINGS,Yes,0,0,0\n"
    "COMMENTS 1,made by test_weather\n"
    "COMMENTS 2,\n"
    "DATA PERIODS,1,1,Data,Sunday, 2/28,3/ 1\n";

/// One EPW record with the given irradiation (Wh/m2) and albedo; other fields plausible.
std::string record(int year, int month, int day, int hour, const std::string& ghi, const std::string& dni,
                   const std::string& dhi, const std::string& albedo = "0.25") {
  std::ostringstream s;
  s << year << ',' << month << ',' << day << ',' << hour << ",60,?9?9?9?9E0?9?9?9?9?9?9?9?9?9?9?9?9?9?9?9*9*9?9?9?9,"
    << "5.0,1.0,80,100000,0,0,300," << ghi << ',' << dni << ',' << dhi
    << ",0,0,0,0,180,2.0,5,5,20,77777,9,999999999,10,0.1,0,88," << albedo << ",0,0\n";
  return s.str();
}

std::string two_days(int year, int first_day_month, int first_day) {
  std::string text = kHeader;
  for (int d = 0; d < 2; ++d)
    for (int h = 1; h <= 24; ++h)
      text += record(year, first_day_month, first_day + d, h, "100", "200", "50");
  return text;
}

shadow::Weather parse(const std::string& text) {
  std::istringstream in(text);
  return shadow::parse_epw(in, "test.epw");
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const shadow::InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Weather, ReadsLocationAndHourEndingRecords) {
  const shadow::Weather w = parse(two_days(2023, 6, 20));
  EXPECT_EQ(w.location.city, "Testville");
  EXPECT_DOUBLE_EQ(w.location.latitude, 49.5);
  EXPECT_DOUBLE_EQ(w.location.longitude, 8.5);
  EXPECT_DOUBLE_EQ(w.location.time_zone_hours, 1.0);
  EXPECT_DOUBLE_EQ(w.location.elevation, 96.0);
  EXPECT_TRUE(w.leap_year_observed);
  ASSERT_EQ(w.hours(), 48u);
  EXPECT_EQ(w.year, 2023);
  // Hour 1 of 20 June ends at 01:00 local standard time (UTC+1): it starts at 23:00 UTC on 19 June.
  EXPECT_EQ(shadow::format_iso8601_utc(w.start_utc[0]), "2023-06-19T23:00:00Z");
  EXPECT_EQ(shadow::format_iso8601_utc(w.start_utc[47]), "2023-06-21T22:00:00Z");
  EXPECT_DOUBLE_EQ(w.global_horizontal[5], 100.0);
  EXPECT_DOUBLE_EQ(w.direct_normal[5], 200.0);
  EXPECT_DOUBLE_EQ(w.diffuse_horizontal[5], 50.0);
  EXPECT_DOUBLE_EQ(w.mean_albedo(), 0.25);
}

TEST(Weather, MissingValuesAreNaN) {
  std::string text = kHeader;
  text += record(2023, 3, 1, 1, "9999", "9999", "", "999");
  text += record(2023, 3, 1, 2, "10", "20", "30", "999");
  const shadow::Weather w = parse(text);
  EXPECT_TRUE(std::isnan(w.global_horizontal[0]));
  EXPECT_TRUE(std::isnan(w.direct_normal[0]));
  EXPECT_TRUE(std::isnan(w.diffuse_horizontal[0]));  // blank
  EXPECT_TRUE(std::isnan(w.albedo[0]));
  EXPECT_TRUE(std::isnan(w.mean_albedo()));
  EXPECT_DOUBLE_EQ(w.diffuse_horizontal[1], 30.0);
}

TEST(Weather, LeapYears) {
  // 29 February in a typical year stamped 2023 (not a leap year): the records go in 2024.
  std::string text = kHeader;
  for (int h = 1; h <= 24; ++h) text += record(2023, 2, 28, h, "0", "0", "0");
  for (int h = 1; h <= 24; ++h) text += record(2023, 2, 29, h, "0", "0", "0");
  for (int h = 1; h <= 24; ++h) text += record(2023, 3, 1, h, "0", "0", "0");
  const shadow::Weather w = parse(text);
  EXPECT_EQ(w.year, 2024);
  EXPECT_EQ(w.start_utc[24] - w.start_utc[0], 86400);
  EXPECT_EQ(w.start_utc[48] - w.start_utc[0], 2 * 86400);
  // Without 29 February, a leap-year stamp places 1 March the day after 28 February.
  std::string plain = kHeader;
  for (int h = 1; h <= 24; ++h) plain += record(2023, 2, 28, h, "0", "0", "0");
  for (int h = 1; h <= 24; ++h) plain += record(2023, 3, 1, h, "0", "0", "0");
  const shadow::Weather p = parse(plain);
  EXPECT_EQ(p.year, 2023);
  EXPECT_EQ(p.start_utc[24] - p.start_utc[0], 86400);
}

TEST(Weather, YearEndWrapsToTheNextYear) {
  std::string text = kHeader;
  text += record(2023, 12, 31, 24, "0", "0", "0");
  text += record(2023, 1, 1, 1, "0", "0", "0");
  const shadow::Weather w = parse(text);
  EXPECT_EQ(w.start_utc[1] - w.start_utc[0], 3600);
}

TEST(Weather, ErrorsNameFileLineAndField) {
  std::string bad_number = two_days(2023, 6, 20);
  bad_number.replace(bad_number.find(",200,"), 5, ",2x0,");
  EXPECT_EQ(error_of(bad_number), "test.epw: line 9, field 15 (direct normal radiation): '2x0' is not a number");

  std::string negative = kHeader + record(2023, 6, 1, 1, "-5", "0", "0");
  EXPECT_EQ(error_of(negative), "test.epw: line 9, field 14 (global horizontal radiation): negative irradiation -5");

  std::string gap = kHeader + record(2023, 6, 1, 1, "0", "0", "0") + record(2023, 6, 1, 3, "0", "0", "0");
  EXPECT_EQ(error_of(gap), "test.epw: line 10, field 4 (hour): records must follow hour by hour: the previous record "
                           "was 6/1 hour 1");

  std::string no_date = kHeader + record(2023, 4, 31, 1, "0", "0", "0");
  EXPECT_EQ(error_of(no_date), "test.epw: line 9, field 3 (day): 4/31 is not a date in 2023");

  std::string hour25 = kHeader + record(2023, 4, 1, 25, "0", "0", "0");
  EXPECT_EQ(error_of(hour25), "test.epw: line 9, field 4 (hour): '25' is not a whole number in [1, 24]");

  std::string short_line = std::string(kHeader) + "2023,6,1,1,60,x,5,1,80,100000,0,0,300,10\n";
  EXPECT_EQ(error_of(short_line), "test.epw: line 9, field 15 (direct normal radiation): the line has only 14 fields");

  EXPECT_EQ(error_of("DESIGN CONDITIONS,0\n"), "test.epw: line 1: the first line of an EPW file is LOCATION,...");
  std::string lat = kHeader;
  lat.replace(lat.find("49.5"), 4, "95.0");
  EXPECT_EQ(error_of(lat + record(2023, 6, 1, 1, "0", "0", "0")), "test.epw: line 1, field 7 (latitude): not in [-90, 90]");

  std::string sub_hourly = kHeader;
  sub_hourly.replace(sub_hourly.find("DATA PERIODS,1,1"), 16, "DATA PERIODS,1,4");
  EXPECT_EQ(error_of(sub_hourly), "test.epw: line 8, field 3 (records per hour): only hourly EPW files are read (this "
                                  "one has 4 records per hour)");
  EXPECT_EQ(error_of(kHeader), "test.epw: line 8: no hourly records after the 8 header lines");
  EXPECT_THROW(shadow::read_epw("/nonexistent/weather.epw"), shadow::InputError);
}

}  // namespace
