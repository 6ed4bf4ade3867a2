// SPDX-License-Identifier: GPL-3.0-or-later
// The weather readers (shadow/epw.hpp): EPW's header, the hour-ending convention, leap years,
// missing values and one error naming file, line and field for a bad file; TMY3 CSV files read
// into the same records as the EPW file of the same hours.
#include <shadow/error.hpp>
#include <shadow/sun.hpp>
#include <shadow/epw.hpp>
#include <shadow/weather.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
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

// An albedo of 0 is what files that do not measure it write (CWEC, TMY2 conversions): read as
// written it took the ground-reflected part off every wall; it is missing, with one warning.
TEST(Weather, ZeroAlbedoIsMissing) {
  std::string text = kHeader;
  text += record(2023, 3, 1, 1, "10", "20", "30", "0.000");
  text += record(2023, 3, 1, 2, "10", "20", "30", "0");
  const shadow::Weather w = parse(text);
  EXPECT_TRUE(std::isnan(w.albedo[0]));
  EXPECT_TRUE(std::isnan(w.albedo[1]));
  EXPECT_TRUE(std::isnan(w.mean_albedo()));
  ASSERT_EQ(w.warnings.size(), 1u);
  EXPECT_EQ(w.warnings[0].to_string(), "test.epw: line 9, field 33 (albedo): albedo 0 in 2 records (the first here), "
                                       "read as missing: files that do not measure the albedo write 0 there");
}

// A UTF-8 byte order mark before LOCATION (an editor's save) was "the first line of an EPW file
// is LOCATION"; TMY3 files already skipped it.
TEST(Weather, ByteOrderMark) {
  const shadow::Weather w = parse("\xEF\xBB\xBF" + two_days(2023, 6, 20));
  EXPECT_EQ(w.location.city, "Testville");
  EXPECT_EQ(w.hours(), 48u);
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

// Typical years mix months of different years: a January from 1996 (a leap year) ahead of a
// February without 29 February was refused ("records must follow hour by hour"); the records go
// in the nearest year they fit, the later of two as near. An actual year from July 2023 to June
// 2024 holds 29 February in its second calendar year (it was pushed to 2025 and refused).
TEST(Weather, RecordsGoInTheNearestYearTheyFit) {
  std::string text = kHeader;
  for (int h = 1; h <= 24; ++h) text += record(1996, 2, 28, h, "0", "0", "0");
  for (int h = 1; h <= 24; ++h) text += record(1996, 3, 1, h, "0", "0", "0");
  const shadow::Weather typical = parse(text);
  EXPECT_EQ(typical.year, 1997);
  ASSERT_EQ(typical.warnings.size(), 1u);  // said, not silent
  EXPECT_EQ(typical.warnings[0].to_string(), "test.epw: line 9, field 1 (year): the records are stamped 1996, but they "
                                             "have no 29 February: they are placed in 1997, the nearest year they fit "
                                             "(typical years mix months of different years)");
  EXPECT_EQ(typical.start_utc[24] - typical.start_utc[0], 86400);
  EXPECT_EQ(typical.start_utc[0], shadow::days_from_civil(1997, 2, 28) * 86400 - 3600);  // UTC+1

  std::string actual = kHeader;
  actual.replace(actual.find("2/28,3/ 1"), 9, "12/31/2023,2/29/2024");
  for (int h = 1; h <= 24; ++h) actual += record(2023, 12, 31, h, "0", "0", "0");
  for (int m = 1; m <= 2; ++m)
    for (int d = 1; d <= (m == 1 ? 31 : 29); ++d)
      for (int h = 1; h <= 24; ++h) actual += record(2024, m, d, h, "0", "0", "0");
  const shadow::Weather wrapped = parse(actual);
  EXPECT_EQ(wrapped.year, 2023);
  EXPECT_EQ(wrapped.start_utc.back(), shadow::days_from_civil(2024, 2, 29) * 86400 + 23 * 3600 - 3600);
  EXPECT_TRUE(wrapped.warnings.empty());

  // 1 March after 28 February, then 29 February, fit no year: the stamped year names the record.
  std::string neither = text;
  for (int h = 1; h <= 24; ++h) neither += record(1996, 2, 29, h, "0", "0", "0");
  EXPECT_EQ(error_of(neither), "test.epw: line 33, field 4 (hour): records must follow hour by hour: the previous "
                               "record was 2/28 hour 24");
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
  // A directory or a device is refused at once (/dev/zero was read without end, growing).
  for (const char* path : {"/tmp", "/dev/zero"}) {
    for (auto read : {&shadow::read_epw, &shadow::read_tmy3}) {
      try {
        read(path);
        ADD_FAILURE() << "no error for " << path;
      } catch (const shadow::InputError& e) {
        EXPECT_NE(std::string(e.what()).find(std::string(path) + ": cannot open the weather file: "), std::string::npos)
            << e.what();
      }
    }
  }
}

// A file cut short, at a line's end or within its last line, is an error naming where it stops:
// read as it was, a year cut in April came out as a whole year's irradiation missing May to
// December, with nothing said.
TEST(Weather, AFileCutShortIsAnError) {
  std::string header = kHeader;
  header.replace(header.find("2/28,3/ 1"), 9, "6/20,6/22");
  std::string whole = header;
  for (int d = 0; d < 3; ++d)
    for (int h = 1; h <= 24; ++h) whole += record(2023, 6, 20 + d, h, "100", "200", "50");
  EXPECT_EQ(parse(whole).hours(), 72u);
  EXPECT_TRUE(parse(whole).warnings.empty());

  // Stopped after the first day: the records follow hour by hour, but end two days early.
  const std::string first_day = whole.substr(0, whole.find("2023,6,21,1,"));
  EXPECT_EQ(error_of(first_day), "test.epw: line 32: the records stop at 6/20 hour 24, but DATA PERIODS (line 8) "
                                 "runs the data to 6/22 hour 24: 48 hours missing: the file is cut short (24 hourly "
                                 "records; if it was shortened on purpose, set the DATA PERIODS end to 6/20)");
  // A day or less missing (leap-year converters are said to drop 31 December): a warning.
  const shadow::Weather two_days_read = parse(whole.substr(0, whole.find("2023,6,22,1,")));
  ASSERT_EQ(two_days_read.warnings.size(), 1u);
  EXPECT_EQ(two_days_read.warnings[0].to_string(),
            "test.epw: line 56: the records stop at 6/21 hour 24, but DATA PERIODS (line 8) runs the data to 6/22 "
            "hour 24: 24 hours missing; read as it is");

  // Stopped within the last line: its cut field would have read as a smaller number (DHI 5 for 50).
  const std::string cut_line = whole.substr(0, whole.find(",50,", whole.find("2023,6,22,24,")) + 2);
  EXPECT_EQ(error_of(cut_line), "test.epw: line 80: the last record has 16 fields, the first 35: is the file cut short?");
  // A record before the last without the optional trailing fields is read as before.
  std::string trimmed = whole;
  const std::size_t second = trimmed.find("2023,6,20,2,");
  const std::size_t albedo = trimmed.find(",0.25,0,0\n", second);
  trimmed.erase(albedo, std::string(",0.25,0,0").size());
  EXPECT_EQ(parse(trimmed).hours(), 72u);

  // The periods that real generators write: M/D/YYYY and YYYY/M/D (Tokyo's file) read alike.
  for (const char* end : {"6/22/2023", "2023/6/22", "2023/06/22"}) {
    std::string dated = whole;
    dated.replace(dated.find("6/20,6/22"), 9, std::string("6/20,") + end);
    EXPECT_EQ(parse(dated).hours(), 72u) << end;
    std::string dated_cut = first_day;
    dated_cut.replace(dated_cut.find("6/20,6/22"), 9, std::string("6/20,") + end);
    EXPECT_NE(error_of(dated_cut).find("the file is cut short"), std::string::npos) << end;
  }

  // A period that runs past 31 December (7/1 to 6/30): records cut before its end, before or
  // after the year's end, are cut short too (they were read as a shorter year, without a word).
  std::string july = header;
  july.replace(july.find("6/20,6/22"), 9, "7/ 1,6/30");
  for (int d = 1; d <= 31; ++d)
    for (int h = 1; h <= 24; ++h) july += record(2023, 7, d, h, "100", "200", "50");
  EXPECT_EQ(error_of(july), "test.epw: line 752: the records stop at 7/31 hour 24, but DATA PERIODS (line 8) runs "
                            "the data to 6/30 hour 24: 8040 hours missing: the file is cut short (744 hourly records; "
                            "if it was shortened on purpose, set the DATA PERIODS end to 7/31)");

  // Records that end where the header ends the data but begin later lost their beginning: an
  // error over a day, a warning for a day or less.
  std::string late = header;
  late.replace(late.find("6/20,6/22"), 9, "6/18,6/22");
  late += whole.substr(header.size());
  EXPECT_EQ(error_of(late), "test.epw: line 9: the records begin at 6/20 hour 1, but DATA PERIODS (line 8) starts "
                            "the data at 6/18 hour 1: 48 hours missing: the file lost its beginning (72 hourly records; "
                            "if it was shortened on purpose, set the DATA PERIODS start to 6/20)");
  late.replace(late.find("6/18,6/22"), 9, "6/19,6/22");
  const shadow::Weather day_late = parse(late);
  ASSERT_EQ(day_late.warnings.size(), 1u);
  EXPECT_EQ(day_late.warnings[0].to_string(), "test.epw: line 9: the records begin at 6/20 hour 1, but DATA PERIODS "
                                              "(line 8) starts the data at 6/19 hour 1: 24 hours missing; read as it is");

  // A period across 31 December whose records lost their first months (the period's end found
  // in the last record's year, its start the year before): an error too. It was read as a
  // shorter year.
  std::string winter = header;
  winter.replace(winter.find("6/20,6/22"), 9, "7/1/2023,1/2/2024");
  for (int d = 1; d <= 2; ++d)
    for (int h = 1; h <= 24; ++h) winter += record(2024, 1, d, h, "100", "200", "50");
  EXPECT_NE(error_of(winter).find("the records begin at 1/1 hour 1, but DATA PERIODS (line 8) starts the data at 7/1 "
                                  "hour 1: 4416 hours missing: the file lost its beginning"),
            std::string::npos)
      << error_of(winter);

  // Records that do not begin where the header starts the data are read as they are.
  EXPECT_EQ(parse(two_days(2023, 6, 20).substr(0, two_days(2023, 6, 20).find("2023,6,21,1,"))).hours(), 24u);
}

// Diffuse horizontal above global horizontal (by 800 Wh/m2 here) cannot be: read as written,
// with one warning naming the first such line and the count; a few Wh/m2 of noise says nothing.
TEST(Weather, DiffuseAboveGlobalWarns) {
  std::string text = kHeader;
  text += record(2023, 6, 1, 1, "100", "200", "105");  // within noise
  text += record(2023, 6, 1, 2, "169", "200", "969");
  text += record(2023, 6, 1, 3, "10", "0", "900");
  const shadow::Weather w = parse(text);
  ASSERT_EQ(w.warnings.size(), 1u);
  EXPECT_EQ(w.warnings[0].to_string(), "test.epw: line 10: diffuse horizontal 969 Wh/m2 exceeds global horizontal 169 "
                                       "(diffuse is part of global); 2 hours like it (this is the first), read as written");
  EXPECT_DOUBLE_EQ(w.diffuse_horizontal[1], 969.0);
  EXPECT_TRUE(parse(two_days(2023, 6, 20)).warnings.empty());
}

// TMY3: the site line (the name quoted, with a comma), the column names, hourly records.
const char* kTmy3Header =
    "722780,\"PHOENIX, SKY HARBOR INTL AP\",AZ,-7.0,33.450,-111.983,337\n"
    "Date (MM/DD/YYYY),Time (HH:MM),ETR (W/m^2),ETRN (W/m^2),GHI (W/m^2),GHI source,GHI uncert (%),"
    "DNI (W/m^2),DNI source,DNI uncert (%),DHI (W/m^2),DHI source,DHI uncert (%),Dry-bulb (C),Dry-bulb source,"
    "Alb (unitless),Alb source\n";

std::string tmy3_record(int year, int month, int day, int hour, const std::string& ghi, const std::string& dni,
                        const std::string& dhi, const std::string& albedo = "0.25") {
  char line[256];
  std::snprintf(line, sizeof line, "%02d/%02d/%04d,%02d:00,0,0,%s,1,8,%s,1,8,%s,1,8,21.5,A,%s,F\n", month, day, year, hour,
                ghi.c_str(), dni.c_str(), dhi.c_str(), albedo.c_str());
  return line;
}

shadow::Weather parse_tmy3(const std::string& text) {
  std::istringstream in(text);
  return shadow::parse_tmy3(in, "test.csv");
}

std::string tmy3_error(const std::string& text) {
  try {
    parse_tmy3(text);
  } catch (const shadow::InputError& e) {
    return e.what();
  }
  return "no error";
}

// Two days of TMY3 records (years mixed, as typical years are) against an EPW file of the same
// hours: the same records, the same instants.
TEST(Tmy3, ReadsTheSameRecordsAsEpw) {
  std::string tmy3 = kTmy3Header, epw = kHeader;
  epw.replace(epw.find("49.5,8.5,1.0,96.0"), 17, "33.450,-111.983,-7.0,337");
  for (int d = 0; d < 2; ++d)
    for (int h = 1; h <= 24; ++h) {
      const int year = d == 0 ? 1991 : 2004;  // typical months mix years
      const std::string ghi = std::to_string(10 * h), dni = std::to_string(20 * h), dhi = std::to_string(5 * h);
      tmy3 += tmy3_record(year, 6, 20 + d, h, ghi, dni, dhi);
      epw += record(year, 6, 20 + d, h, ghi, dni, dhi);
    }
  const shadow::Weather t = parse_tmy3(tmy3);
  const shadow::Weather e = parse(epw);
  EXPECT_EQ(t.location.city, "PHOENIX, SKY HARBOR INTL AP");
  EXPECT_EQ(t.location.region, "AZ");
  EXPECT_EQ(t.location.wmo, "722780");
  EXPECT_EQ(t.location.source, "TMY3");
  EXPECT_EQ(t.location.latitude, 33.45);
  EXPECT_EQ(t.location.longitude, -111.983);
  EXPECT_EQ(t.location.time_zone_hours, -7.0);
  EXPECT_EQ(t.location.elevation, 337.0);
  ASSERT_EQ(t.hours(), 48u);
  EXPECT_EQ(t.year, 1991);
  EXPECT_EQ(t.start_utc, e.start_utc);
  EXPECT_EQ(t.month, e.month);
  EXPECT_EQ(t.day, e.day);
  EXPECT_EQ(t.hour, e.hour);
  EXPECT_EQ(t.record_year, e.record_year);
  EXPECT_EQ(t.global_horizontal, e.global_horizontal);
  EXPECT_EQ(t.direct_normal, e.direct_normal);
  EXPECT_EQ(t.diffuse_horizontal, e.diffuse_horizontal);
  EXPECT_EQ(t.albedo, e.albedo);
  EXPECT_EQ(t.dry_bulb[0], 21.5);
  // Hour 01:00 of 20 June covers 00:00-01:00 local standard time (UTC-7): 07:00 UTC.
  EXPECT_EQ(shadow::format_iso8601_utc(t.start_utc[0]), "1991-06-20T07:00:00Z");
  EXPECT_EQ(shadow::format_iso8601_utc(t.start_utc[47] + 3600), "1991-06-22T07:00:00Z");
}

TEST(Tmy3, MissingValuesCrlfAndOptionalColumns) {
  std::string text = kTmy3Header;
  text += tmy3_record(2001, 3, 1, 1, "-9900", "", "5", "-9900");
  text += tmy3_record(2001, 3, 1, 2, "7", "8", "9", "1.5");
  for (std::size_t at = text.find('\n'); at != std::string::npos; at = text.find('\n', at + 2)) text.replace(at, 1, "\r\n");
  const shadow::Weather w = parse_tmy3(text);
  ASSERT_EQ(w.hours(), 2u);
  EXPECT_TRUE(std::isnan(w.global_horizontal[0]));
  EXPECT_TRUE(std::isnan(w.direct_normal[0]));
  EXPECT_EQ(w.diffuse_horizontal[0], 5.0);
  EXPECT_TRUE(std::isnan(w.albedo[0]));
  EXPECT_TRUE(std::isnan(w.albedo[1]));  // 1.5 is no reflectance
  EXPECT_EQ(w.direct_normal[1], 8.0);
  // Without the dry bulb and albedo columns: NaN.
  const std::string bare = "1,Site,XX,0,10,20,5\nDate (MM/DD/YYYY),Time (HH:MM),GHI (W/m^2),DNI (W/m^2),DHI (W/m^2)\n"
                           "03/01/2010,01:00,0,0,0\n03/01/2010,02:00,0,0,0\n";
  const shadow::Weather b = parse_tmy3(bare);
  ASSERT_EQ(b.hours(), 2u);
  EXPECT_TRUE(std::isnan(b.albedo[1]));
  EXPECT_TRUE(std::isnan(b.dry_bulb[1]));
  EXPECT_TRUE(std::isnan(b.mean_albedo()));
}

TEST(Tmy3, ErrorsNameFileLineAndField) {
  std::string bad = std::string(kTmy3Header) + tmy3_record(2001, 6, 1, 1, "1", "2x0", "3");
  EXPECT_EQ(tmy3_error(bad), "test.csv: line 3, field 8 (DNI (W/m^2)): '2x0' is not a number");
  EXPECT_EQ(tmy3_error(std::string(kTmy3Header) + tmy3_record(2001, 6, 1, 1, "-5", "0", "0")),
            "test.csv: line 3, field 5 (GHI (W/m^2)): negative irradiation -5");
  EXPECT_EQ(tmy3_error(std::string(kTmy3Header) + "6-1-2001,01:00,0,0,0,1,8,0,1,8,0,1,8,20,A,0.2,F\n"),
            "test.csv: line 3, field 1 (Date (MM/DD/YYYY)): '6-1-2001' is not a date MM/DD/YYYY");
  EXPECT_EQ(tmy3_error(std::string(kTmy3Header) + "06/01/2001,01:30,0,0,0,1,8,0,1,8,0,1,8,20,A,0.2,F\n"),
            "test.csv: line 3, field 2 (Time (HH:MM)): '01:30' is not an hour 01:00..24:00 (the hour ending the record)");
  EXPECT_EQ(tmy3_error(std::string(kTmy3Header) + tmy3_record(2001, 4, 31, 1, "0", "0", "0")),
            "test.csv: line 3, field 1 (Date (MM/DD/YYYY)): 4/31 is not a date in 2001");
  EXPECT_EQ(tmy3_error(std::string(kTmy3Header) + tmy3_record(2001, 6, 1, 1, "0", "0", "0") +
                       tmy3_record(2001, 6, 1, 3, "0", "0", "0")),
            "test.csv: line 4, field 2 (Time (HH:MM)): records must follow hour by hour: the previous record was 6/1 "
            "hour 1");
  std::string no_dni = kTmy3Header;
  no_dni.replace(no_dni.find("DNI (W/m^2)"), 11, "DNI");
  EXPECT_EQ(tmy3_error(no_dni), "test.csv: line 2: no column named 'DNI (W/m^2)' (the second line of a TMY3 file names "
                                "the columns)");
  EXPECT_EQ(tmy3_error("722780,Site,AZ,-7.0,33.4\n"),
            "test.csv: line 1: the first line of a TMY3 file is the site: USAF,name,state,time zone,latitude,longitude,"
            "elevation (it has 5 fields, 7 are needed)");
  EXPECT_EQ(tmy3_error("1,Site,XX,0,95,20,5\n"), "test.csv: line 1, field 5 (latitude): not in [-90, 90]");
  EXPECT_EQ(tmy3_error(kTmy3Header), "test.csv: line 2: no hourly records after the 2 header lines");
  EXPECT_EQ(tmy3_error(std::string(kTmy3Header) + "06/01/2001,01:00,0,0,0\n"),
            "test.csv: line 3, field 8 (DNI (W/m^2)): the line has only 5 fields");
}

// read_weather: a name ending in .csv is TMY3, any other EPW.
// A TMY3 file states no period (a short one may be meant), but a last line cut in the middle is
// an error, not a smaller last value (an albedo of 0.2 for 0.25).
TEST(Tmy3, ALastLineCutShortIsAnError) {
  const std::string last = tmy3_record(2001, 6, 1, 2, "0", "0", "0");
  const std::string cut = std::string(kTmy3Header) + tmy3_record(2001, 6, 1, 1, "0", "0", "0") +
                          last.substr(0, last.find(",F") - 1) + "\n";
  EXPECT_EQ(tmy3_error(cut), "test.csv: line 4: the last record has 16 fields, the first 17: is the file cut short?");
}

// A TMY3 file is a year of hours (1/1 hour 1 to 12/31 hour 24) and states no other period:
// records that begin on 1 January and stop more than a day early are a file cut short (it would
// read as a shorter year without a word); a day or less missing is a warning; records that begin
// later are part of a year, read as they are.
TEST(Tmy3, AYearCutShortIsAnError) {
  auto year_to = [](int month, int day, int hour) {
    std::string text = kTmy3Header;
    for (int m = 1, d = 1, h = 1;;) {
      text += tmy3_record(1990 + m, m, d, h, "0", "0", "0");
      if (m == month && d == day && h == hour) break;
      if (++h > 24) {
        h = 1;
        static const int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
        if (++d > kDays[m - 1]) d = 1, ++m;
      }
    }
    return text;
  };
  const shadow::Weather whole = parse_tmy3(year_to(12, 31, 24));
  EXPECT_EQ(whole.hours(), 8760u);
  EXPECT_TRUE(whole.warnings.empty());
  EXPECT_EQ(tmy3_error(year_to(5, 12, 7)),
            "test.csv: line 3153: the records stop at 5/12 hour 7, but a TMY3 year runs from 1/1 hour 1 to 12/31 hour "
            "24: 5609 hours missing: the file is cut short (3151 hourly records; for part of the year, read the whole "
            "file and choose the days: `shadow irradiance --from/--to`)");
  const shadow::Weather day_short = parse_tmy3(year_to(12, 30, 24));
  EXPECT_EQ(day_short.hours(), 8736u);
  ASSERT_EQ(day_short.warnings.size(), 1u);
  EXPECT_EQ(day_short.warnings[0].to_string(),
            "test.csv: line 8738: the records stop at 12/30 hour 24, but a TMY3 year runs from 1/1 hour 1 to 12/31 hour "
            "24: 24 hours missing; read as it is");
  // A year and a few hours of the next (records that wrap past 12/31 hour 24): whole.
  std::string longer = year_to(12, 31, 24);
  for (int h = 1; h <= 5; ++h) longer += tmy3_record(2002, 1, 1, h, "0", "0", "0");
  EXPECT_TRUE(parse_tmy3(longer).warnings.empty());
  // Records that hold 29 February count the days to 31 December in a leap year.
  std::string leap = kTmy3Header;
  for (int m = 1, d = 1; m <= 2; ++d) {
    if (d > (m == 1 ? 31 : 29)) d = 1, ++m;
    if (m > 2) break;
    for (int h = 1; h <= 24; ++h) leap += tmy3_record(2004, m, d, h, "0", "0", "0");
  }
  EXPECT_NE(tmy3_error(leap).find("the records stop at 2/29 hour 24, but a TMY3 year runs from 1/1 hour 1 to 12/31 hour "
                                  "24: 7344 hours missing"),
            std::string::npos)
      << tmy3_error(leap);
  // Part of a year that does not begin on 1 January: read as it is, without a word.
  std::string june = kTmy3Header;
  for (int h = 1; h <= 24; ++h) june += tmy3_record(2001, 6, 1, h, "0", "0", "0");
  EXPECT_TRUE(parse_tmy3(june).warnings.empty());
}

TEST(Tmy3, ReadWeatherChoosesByName) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "libshadow_test_tmy3";
  std::filesystem::create_directories(dir);
  const std::string csv = (dir / "site.CSV").string(), epw = (dir / "site.epw").string();
  std::ofstream(csv) << kTmy3Header << tmy3_record(2001, 6, 1, 1, "0", "0", "0");
  std::ofstream(epw) << kHeader << record(2001, 6, 1, 1, "0", "0", "0");
  EXPECT_EQ(shadow::read_weather(csv).location.source, "TMY3");
  EXPECT_EQ(shadow::read_weather(epw).location.source, "Test");
  EXPECT_EQ(shadow::read_tmy3(csv).hours(), 1u);
  EXPECT_THROW(shadow::read_weather((dir / "missing.csv").string()), shadow::InputError);
  std::filesystem::remove_all(dir);
}

}  // namespace
