#pragma once

// The name tables of scene's enums are base's (base/enum_names.hpp), under scene's own names, so
// that scene's enums and their callers read `scene::to_string`, `scene::parse_name<View>`.
#include <penumbra/base/enum_names.hpp>

namespace penumbra::scene {

using base::choices;
using base::EnumName;
using base::has_values_up_to;
using base::is_enumerator;
using base::name_list;
using base::name_of;
using base::NamedEnum;
using base::names;
using base::names_each_value;
using base::parse_name;
using base::to_string;

}  // namespace penumbra::scene
