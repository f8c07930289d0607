// Comma-separated values as RFC 4180 writes them, for batch manifests and
// summaries: fields optionally in double quotes (a quote inside written
// twice; commas and line breaks allowed inside quotes), LF or CRLF line ends,
// a UTF-8 byte order mark at the start ignored.
#ifndef SYLVA_UI_BATCH_CSV_H_
#define SYLVA_UI_BATCH_CSV_H_

#include <string>
#include <vector>

namespace sylva {

struct CsvRecord {
  int line = 0;  // 1-based line of the file where the record starts
  std::vector<std::string> fields;
};

// Parses CSV text. Lines that are empty (only spaces) or start with '#' are
// skipped. Fields are returned as written, without trimming (quoted or not).
// Throws InputError("SOURCE:LINE", ...) for an unterminated quoted field or
// text after a closing quote.
std::vector<CsvRecord> ParseCsv(const std::string& text, const std::string& source);

// A field as CSV writes it: quoted when it holds a comma, a quote, a line
// break or leading/trailing spaces, or starts with '#'.
std::string CsvField(const std::string& value);
// Fields joined with commas, ending in "\n".
std::string CsvLine(const std::vector<std::string>& fields);

}  // namespace sylva

#endif  // SYLVA_UI_BATCH_CSV_H_
