#pragma once
/// JUnit XML (the Apache Ant junit task's format, as Jenkins, GitLab and
/// GitHub test reporters read it; schema: Ant's JUnit.xsd): one <testsuite>
/// per input file, one <testcase> per glyph (a font) or spline, a
/// <failure> per failing case carrying each finding's message, an <error>
/// for an invalid input. Written in pieces (report/corpus.hpp streams it).
#include <string>
#include <string_view>

#include "report/corpus.hpp"

namespace cmr::report {

/// Text safe in XML 1.0 content and attribute values: & < > " ' as
/// entities; characters XML 1.0 forbids (C0 controls other than tab, LF, CR;
/// U+FFFE, U+FFFF) and bytes that are not well-formed UTF-8 as U+FFFD.
std::string xml_escape(std::string_view text);

/// The declaration and the opening <testsuites>.
std::string junit_header();
/// One file's <testsuite> (timestamp ISO 8601 without zone, as the schema asks).
std::string junit_suite(const FileRecord& file, int id, const std::string& timestamp, const std::string& hostname);
/// The closing </testsuites>.
std::string junit_footer();

}  // namespace cmr::report
