/* semloc — strict YAML syntax check with libyaml's event parser. */
#include "YamlSyntax.h"

#include <yaml.h>

namespace semloc::detail
{
std::string yamlSyntaxError(const std::string& text)
{
    yaml_parser_t parser;
    if (!yaml_parser_initialize(&parser))
    {
        return "cannot start the YAML parser (out of memory)";
    }
    yaml_parser_set_input_string(&parser, reinterpret_cast<const unsigned char*>(text.data()),
                                 text.size());
    std::string error;
    for (bool done = false; !done;)
    {
        yaml_event_t event;
        if (!yaml_parser_parse(&parser, &event))
        {
            // Marks are 0-based; editors count from 1.
            error = "line " + std::to_string(parser.problem_mark.line + 1) + ", column " +
                    std::to_string(parser.problem_mark.column + 1) +
                    ": YAML syntax error: " + (parser.problem ? parser.problem : "unknown error");
            if (parser.context)
            {
                error += std::string(" (") + parser.context + ")";
            }
            break;
        }
        done = event.type == YAML_STREAM_END_EVENT;
        yaml_event_delete(&event);
    }
    yaml_parser_delete(&parser);
    return error;
}
}  // namespace semloc::detail
