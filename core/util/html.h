// Text for HTML pages (the report, the batch summary).
#ifndef SYLVA_CORE_UTIL_HTML_H_
#define SYLVA_CORE_UTIL_HTML_H_

#include <string>

namespace sylva {

// `text` with & < > " ' escaped: safe in element content and in attribute
// values quoted either way.
std::string HtmlEscape(const std::string& text);

}  // namespace sylva

#endif  // SYLVA_CORE_UTIL_HTML_H_
