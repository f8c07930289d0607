#include "core/util/html.h"

#include <gtest/gtest.h>

namespace sylva {
namespace {

TEST(HtmlEscapeTest, EscapesWhatBreaksContentAndQuotedAttributes) {
  EXPECT_EQ(HtmlEscape("tree 'A' & <b>\"B\"</b>"),
            "tree &#39;A&#39; &amp; &lt;b&gt;&quot;B&quot;&lt;/b&gt;");
  EXPECT_EQ(HtmlEscape("plain_name-01.png"), "plain_name-01.png");
  EXPECT_EQ(HtmlEscape(""), "");
}

}  // namespace
}  // namespace sylva
