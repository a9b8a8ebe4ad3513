# Turns params/defaults.json into a C++ source holding it as a string.
file(READ ${IN} CONTENT)
file(WRITE ${OUT} "// generated from params/defaults.json: do not edit\n#include <string_view>\nnamespace tetmvs { extern const std::string_view kDefaultParamsJson; const std::string_view kDefaultParamsJson = R\"__json__(${CONTENT})__json__\"; }\n")
