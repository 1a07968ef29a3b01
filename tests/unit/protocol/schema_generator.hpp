#pragma once

// What proto/v1/common.schema.json restates of the C++ tables, for clients that cannot read C++:
// scene's mode table, each setting's range (kSettingRanges: type, minimum, maximum and, where the
// row has one, its summary as the description; a setting that a state holds is required there)
// and the client message types (the request variant). The rest of the file is written by hand.
// update_schema writes these parts into the file (scripts/update-schema.sh) and
// SchemaAgreement.CommonSchemaIsGenerated fails while the committed file differs.

#include <penumbra/base/result.hpp>

#include <string>
#include <string_view>

namespace penumbra::protocol::test {

// `committed`, the text of common.schema.json, with its generated parts written from the tables,
// two-space indented as the file is; an error where the text is not a JSON object with `$defs`.
base::Result<std::string> generated_common_schema(std::string_view committed);

}  // namespace penumbra::protocol::test
