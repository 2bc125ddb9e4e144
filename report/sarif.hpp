#pragma once
/// SARIF 2.1.0 (OASIS Static Analysis Results Interchange Format; GitHub
/// code scanning reads it): one run whose tool.driver is cmr with one rule
/// per gate (id, name, shortDescription, fullDescription, help,
/// defaultConfiguration), and one result per finding: ruleId and ruleIndex,
/// level "error", message.text, a location with the file
/// (physicalLocation.artifactLocation.uri: relative to the source root,
/// the working folder or --source-root, with uriBaseId SRCROOT, which
/// run.originalUriBaseIds maps to the root's file: URI; a file outside it
/// as an absolute file: URI) and the glyph/contour/node as a logical location, and
/// partialFingerprints with the finding's stable key. With a baseline each
/// result has its baselineState ("new" or "unchanged"). Written in pieces.
#include <string>

#include "report/corpus.hpp"

namespace cmr::report {

/// The rule ids of a run, in ruleIndex order: the check (when required),
/// each type gate, and "invalid-input".
std::vector<std::string> sarif_rule_ids(const ReportOptions& options);
/// The id relative artifact URIs are resolved against.
inline constexpr const char* kSarifRootId = "SRCROOT";
/// The file: URI of the folder `root` ("" is the working folder), ending in
/// '/' as SARIF's originalUriBaseIds asks (§3.14.14).
std::string source_uri_base(const std::string& root);
/// The document up to the opening of "results"; `root_uri` (source_uri_base)
/// becomes originalUriBaseIds.SRCROOT.
std::string sarif_header(const ReportOptions& options, const std::string& root_uri);
/// One result (without separator) for a finding of the file whose artifact
/// URI is `uri` (source_uri; `relative`: under the root, so with uriBaseId);
/// baseline_state null without a baseline.
std::string sarif_result(const Finding& f, const std::string& uri, bool relative, const ReportOptions& options,
                         const char* baseline_state);
/// A result for an invalid input (rule "invalid-input").
std::string sarif_invalid(const std::string& uri, bool relative, const std::string& name, const std::string& error,
                          const ReportOptions& options);
/// Closes results, the run and the log.
std::string sarif_footer();
/// A URI reference for a path: relative paths percent-encoded (RFC 3986,
/// '/' kept), absolute ones as file:// URIs.
std::string path_uri(const std::string& path);

}  // namespace cmr::report
