/* semloc — strict YAML reading with libyaml's event parser. */
#include "world/YamlSyntax.h"

#include <yaml.h>

#include <algorithm>
#include <exception>
#include <memory>
#include <set>
#include <vector>

namespace semloc::detail
{
namespace
{
using node_t = mrpt::containers::yaml::node_t;

/** "line L, column C: " of a 0-based libyaml mark (editors count from 1). */
std::string at(const yaml_mark_t& m)
{
    return "line " + std::to_string(m.line + 1) + ", column " + std::to_string(m.column + 1) + ": ";
}

/** An open map or sequence: its node (in its parent, or the document; neither moves while
 *  it is open), and for maps the key waiting for its value. node_t has no move operations:
 *  nodes are built in place, never copied once filled. */
struct Open
{
    node_t* node = nullptr;
    bool haveKey = false;
    std::string key;
    std::map<std::string, size_t> keyLine;  // each key and its 0-based line
    /** A sequence whose elements go to the sink (under this key), and how many went. */
    const std::string* streamedKey = nullptr;
    size_t streamed = 0;
};

/** `n` with the position of the event that starts it. */
node_t marked(node_t n, const yaml_event_t& e)
{
    n.marks.line = static_cast<int>(e.start_mark.line);
    n.marks.column = static_cast<int>(e.start_mark.column);
    n.marks.input_pos = e.start_mark.index;
    return n;
}

/** A scalar event's node: null for the plain forms YAML's core schema reads as null. */
node_t scalarNode(const yaml_event_t& e)
{
    const std::string value(reinterpret_cast<const char*>(e.data.scalar.value),
                            e.data.scalar.length);
    static const std::set<std::string> nulls = {"", "~", "null", "Null", "NULL"};
    node_t n;
    if (!(e.data.scalar.style == YAML_PLAIN_SCALAR_STYLE && nulls.count(value)))
    {
        n.d.emplace<mrpt::containers::yaml::scalar_t>().emplace<std::string>(value);
    }
    return n;
}

/** The event parser: owns libyaml's parser and the event being handled. */
class Reader
{
public:
    Reader(const YamlRead& read, const YamlElementSink* sink) : m_read(read), m_sink(sink)
    {
        m_ok = yaml_parser_initialize(&m_parser) != 0;
        if (m_ok)
        {
            yaml_parser_set_input(&m_parser, &Reader::input, this);
        }
    }
    ~Reader()
    {
        if (m_haveEvent)
        {
            yaml_event_delete(&m_event);
        }
        if (m_ok)
        {
            yaml_parser_delete(&m_parser);
        }
    }
    Reader(const Reader&) = delete;
    Reader& operator=(const Reader&) = delete;

    /** Reads the whole document into `doc`: "" or the first error. */
    std::string read(node_t& doc)
    {
        if (!m_ok)
        {
            return "cannot start the YAML parser (out of memory)";
        }
        m_doc = &doc;
        for (;;)
        {
            if (!next())
            {
                if (m_readError)
                {
                    std::rethrow_exception(m_readError);
                }
                return syntaxError();
            }
            if (m_event.type == YAML_STREAM_END_EVENT)
            {
                return {};
            }
            if (std::string error = handle(m_event); !error.empty())
            {
                return error;
            }
        }
    }

private:
    /** libyaml's read handler: the next bytes from m_read (1: read, 0: failed). */
    static int input(void* data, unsigned char* buffer, size_t size, size_t* sizeRead)
    {
        auto& self = *static_cast<Reader*>(data);
        try
        {
            *sizeRead = self.m_read(reinterpret_cast<char*>(buffer), size);
            return 1;
        }
        catch (...)
        {
            self.m_readError = std::current_exception();
            *sizeRead = 0;
            return 0;
        }
    }

    /** The parser's error, where it is. */
    std::string syntaxError() const
    {
        std::string error = at(m_parser.problem_mark) + "YAML syntax error: " +
                            (m_parser.problem ? m_parser.problem : "unknown error");
        if (m_parser.context)
        {
            error += std::string(" (") + m_parser.context + ")";
        }
        return error;
    }

    /** True if the event is a key of the innermost open map. */
    bool keyNext() const
    {
        return !m_open.empty() && m_open.back().node->isMap() && !m_open.back().haveKey;
    }

    /** One event (not the stream's end) into the document: "" or an error. */
    std::string handle(const yaml_event_t& e)
    {
        switch (e.type)
        {
            case YAML_DOCUMENT_START_EVENT:
                if (m_haveDoc)
                {
                    return at(e.start_mark) +
                           "a second YAML document: the file must hold one (remove the "
                           "'---' and what follows, or merge the documents)";
                }
                m_haveDoc = true;
                return {};
            case YAML_ALIAS_EVENT:
                return at(e.start_mark) + "YAML alias '*" +
                       reinterpret_cast<const char*>(e.data.alias.anchor) +
                       "': aliases are not supported (write the value out)";
            case YAML_SCALAR_EVENT:
                return scalar(e);
            case YAML_SEQUENCE_START_EVENT:
            case YAML_MAPPING_START_EVENT:
                return openCollection(e);
            case YAML_SEQUENCE_END_EVENT:
            case YAML_MAPPING_END_EVENT:
                m_open.pop_back();
                if (!m_open.empty() && m_open.back().streamedKey)
                {
                    // A map or sequence of a streamed sequence is complete: handed over.
                    Open& list = m_open.back();
                    m_sink->take(*list.streamedKey, list.streamed++,
                                 list.node->asSequence().back());
                    list.node->asSequence().pop_back();
                }
                return {};
            default:
                return {};
        }
    }

    /** A scalar: the key of the innermost open map (once per map), or a value placed. */
    std::string scalar(const yaml_event_t& e)
    {
        if (!keyNext())
        {
            place(marked(scalarNode(e), e));
            return {};
        }
        Open& m = m_open.back();
        const std::string key(reinterpret_cast<const char*>(e.data.scalar.value),
                              e.data.scalar.length);
        const auto [it, added] = m.keyLine.emplace(key, e.start_mark.line);
        if (!added)
        {
            return at(e.start_mark) + "key '" + key + "' repeated (first on line " +
                   std::to_string(it->second + 1) + "): a YAML map takes each key once";
        }
        m.key = key;
        m.haveKey = true;
        return {};
    }

    /** A map or sequence, placed empty and open until its end event. */
    std::string openCollection(const yaml_event_t& e)
    {
        if (m_open.size() >= kMaxYamlDepth)
        {
            return at(e.start_mark) + "nested deeper than " + std::to_string(kMaxYamlDepth) +
                   " levels";
        }
        if (keyNext())
        {
            return at(e.start_mark) + "a map key must be a scalar";
        }
        node_t n;
        if (e.type == YAML_MAPPING_START_EVENT)
        {
            n.d.emplace<mrpt::containers::yaml::map_t>();
        }
        else
        {
            n.d.emplace<mrpt::containers::yaml::sequence_t>();
        }
        Open o;
        o.streamedKey = e.type == YAML_SEQUENCE_START_EVENT ? streamedKey() : nullptr;
        o.node = place(marked(n, e));
        m_open.push_back(o);
        return {};
    }

    /** The sink's key when a sequence starting now is the value of one of its keys in the
     *  document's top-level map, else null. */
    const std::string* streamedKey() const
    {
        if (!m_sink || m_open.size() != 1 || !m_open[0].node->isMap() || !m_open[0].haveKey)
        {
            return nullptr;
        }
        const auto it = m_sink->keys.find(m_open[0].key);
        return it == m_sink->keys.end() ? nullptr : &*it;
    }

    /** Places a new node (a scalar, or a collection still empty) where the document is at;
     *  a scalar element of a streamed sequence goes to the sink (nullptr returned). */
    node_t* place(const node_t& n)
    {
        if (m_open.empty())
        {
            *m_doc = n;
            return m_doc;
        }
        Open& parent = m_open.back();
        if (parent.streamedKey && !n.isMap() && !n.isSequence())
        {
            m_sink->take(*parent.streamedKey, parent.streamed++, n);
            return nullptr;
        }
        if (parent.node->isSequence())
        {
            parent.node->asSequence().push_back(n);
            return &parent.node->asSequence().back();
        }
        parent.haveKey = false;
        const auto it =
            parent.node->asMap().emplace(node_t(parent.key), n).first;  // keys are unique
        return &it->second;
    }

    /** Parses the next event into m_event; false on a syntax error. */
    bool next()
    {
        if (m_haveEvent)
        {
            yaml_event_delete(&m_event);
            m_haveEvent = false;
        }
        if (!yaml_parser_parse(&m_parser, &m_event))
        {
            return false;
        }
        m_haveEvent = true;
        return true;
    }

    const YamlRead& m_read;
    const YamlElementSink* m_sink = nullptr;
    std::exception_ptr m_readError;  // what m_read threw
    yaml_parser_t m_parser{};
    yaml_event_t m_event{};
    bool m_ok = false;
    bool m_haveEvent = false;
    node_t* m_doc = nullptr;   // the document being read
    std::vector<Open> m_open;  // the maps and sequences open, innermost last
    bool m_haveDoc = false;    // a document has started
};
}  // namespace

std::string parseYaml(const std::string& text, node_t& doc)
{
    size_t at = 0;
    const YamlRead read = [&](char* buf, size_t n)
    {
        n = std::min(n, text.size() - at);
        std::copy_n(text.data() + at, n, buf);
        at += n;
        return n;
    };
    return parseYaml(read, doc);
}

std::string parseYaml(const YamlRead& read, node_t& doc, const YamlElementSink* sink)
{
    doc = node_t();
    return Reader(read, sink).read(doc);
}
}  // namespace semloc::detail
