// XML text escaping shared by the VTU and PVD writers (and the PVD reader used on restart).
#pragma once

#include <string>
#include <string_view>

namespace quarry {

// Replaces & < > " ' by their XML entities.
std::string xml_escaped(std::string_view text);
// Inverse of xml_escaped (only those five entities).
std::string xml_unescaped(std::string_view text);

}  // namespace quarry
