#include "ui/batch/csv.h"

#include "core/util/check.h"

namespace sylva {
namespace {

constexpr char kUtf8Bom[] = "\xEF\xBB\xBF";

bool IsBlankOrComment(const std::string& text, size_t begin) {
  size_t i = begin;
  while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
  return i >= text.size() || text[i] == '\n' || text[i] == '\r' || (i == begin && text[i] == '#');
}

size_t EndOfLine(const std::string& text, size_t at) {
  const size_t end = text.find('\n', at);
  return end == std::string::npos ? text.size() : end + 1;
}

// Reads the CSV record starting at `*at` (line `*line`); moves both past it.
class RecordReader {
 public:
  RecordReader(const std::string& text, const std::string& source) : text_(text), source_(source) {}

  CsvRecord Read(size_t* at, int* line) {
    CsvRecord record;
    record.line = *line;
    std::string field;
    while (true) {
      if (*at < text_.size() && text_[*at] == '"') {
        ReadQuoted(at, line, record.line, &field);
      } else {
        while (*at < text_.size() && text_[*at] != ',' && text_[*at] != '\n' &&
               !(text_[*at] == '\r' && (*at + 1 == text_.size() || text_[*at + 1] == '\n'))) {
          field += text_[(*at)++];
        }
      }
      record.fields.push_back(field);
      field.clear();
      if (*at < text_.size() && text_[*at] == ',') {
        ++*at;
        continue;
      }
      if (*at < text_.size() && text_[*at] == '\r') ++*at;
      if (*at < text_.size() && text_[*at] == '\n') ++*at;
      ++*line;
      return record;
    }
  }

 private:
  void ReadQuoted(size_t* at, int* line, int record_line, std::string* field) {
    ++*at;  // the opening quote
    while (true) {
      SYLVA_CHECK_INPUT(*at < text_.size(), source_ + ":" + std::to_string(record_line))
          << "a quoted field is not closed (a '\"' is missing)";
      const char c = text_[(*at)++];
      if (c == '"') {
        if (*at < text_.size() && text_[*at] == '"') {
          *field += '"';
          ++*at;
          continue;
        }
        break;
      }
      if (c == '\n') ++*line;
      *field += c;
    }
    SYLVA_CHECK_INPUT(
        *at >= text_.size() || text_[*at] == ',' || text_[*at] == '\n' || text_[*at] == '\r',
        source_ + ":" + std::to_string(*line))
        << "text after a closing quote (write a quote inside a quoted field as \"\")";
  }

  const std::string& text_;
  const std::string& source_;
};

}  // namespace

std::vector<CsvRecord> ParseCsv(const std::string& text, const std::string& source) {
  std::vector<CsvRecord> records;
  size_t at = text.rfind(kUtf8Bom, 0) == 0 ? 3 : 0;
  int line = 1;
  RecordReader reader(text, source);
  while (at < text.size()) {
    if (IsBlankOrComment(text, at)) {
      at = EndOfLine(text, at);
      ++line;
      continue;
    }
    records.push_back(reader.Read(&at, &line));
  }
  return records;
}

std::string CsvField(const std::string& value) {
  const bool quote = value.find_first_of(",\"\r\n") != std::string::npos ||
                     (!value.empty() && (value.front() == ' ' || value.back() == ' ' ||
                                         value.front() == '#' || value.front() == '\t'));
  if (!quote) return value;
  std::string out = "\"";
  for (char c : value) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string CsvLine(const std::vector<std::string>& fields) {
  std::string line;
  for (size_t i = 0; i < fields.size(); ++i) line += (i > 0 ? "," : "") + CsvField(fields[i]);
  return line + "\n";
}

}  // namespace sylva
