// The live preview's single page (HTML, CSS and script in one), embedded in the binary.
#pragma once

#include <string_view>

namespace wsd::app {

std::string_view preview_page_html();

}  // namespace wsd::app
