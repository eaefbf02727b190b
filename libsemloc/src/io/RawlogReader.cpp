/* semloc — RawlogReader: a rawlog entry by entry, every early stop located. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/io/InputFile.h>
#include <semloc/io/RawlogReader.h>
#include <semloc/io/RawlogWriter.h>

#include <filesystem>
#include <new>
#include <regex>
#include <system_error>

namespace semloc
{
namespace
{
using Kind = RawlogReader::TDefect::Kind;

/** The class CArchive could not find, from its message (also when nested inside another
 *  object's "Original exception" text); empty if the message is about something else. */
std::string unregisteredClass(const std::string& what)
{
    static const std::regex re("Stored object has class '([^']*)' which is not registered");
    std::smatch m;
    return std::regex_search(what, m, re) ? m[1].str() : std::string();
}

/** The innermost of MRPT's nested messages ("Message:  <text>" lines, outermost first). */
std::string innermostMessage(const std::string& what)
{
    const auto p = what.rfind("Message:");
    if (p == std::string::npos)
    {
        return what.substr(0, what.find('\n'));
    }
    const auto b = what.find_first_not_of(' ', p + 8);
    return b == std::string::npos ? std::string() : what.substr(b, what.find('\n', b) - b);
}

bool isRawlogEntry(const mrpt::serialization::CSerializable& obj)
{
    const auto* c = obj.GetRuntimeClass();
    return c->derivedFrom(CLASS_ID(mrpt::obs::CObservation)) ||
           c == CLASS_ID(mrpt::obs::CSensoryFrame) || c == CLASS_ID(mrpt::obs::CActionCollection);
}
}  // namespace

struct RawlogReader::TStream
{
    mrpt::io::CFileGZInputStream in;
    std::optional<mrpt::serialization::CArchiveStreamBase<mrpt::io::CFileGZInputStream>> arch;
};

RawlogReader::RawlogReader(const std::string& path) : m_path(path), m_stream(new TStream)
{
    (void)checkInputFile(path, "rawlog", InputKind::Rawlog);
    std::string why;
    if (!m_stream->in.open(path, why))
    {
        THROW_EXCEPTION("cannot open rawlog '" + path + "': " + why);
    }
    m_stream->arch.emplace(m_stream->in);
}

RawlogReader::~RawlogReader() = default;

bool RawlogReader::readObject(mrpt::serialization::CSerializable::Ptr& obj)
{
    auto& in = m_stream->in;
    const uint64_t byte = m_byte = in.getPosition();
    auto fail = [&](Kind kind, std::string className, std::string detail) {
        m_defect = TDefect{kind, m_entry, byte, std::move(className), std::move(detail)};
    };
    try
    {
        obj = m_stream->arch->ReadObject();
    }
    catch (const mrpt::serialization::CExceptionEOF&)
    {
        // CArchive throws this when the entry's first byte cannot be read: a clean end
        // only if the stream really is at its end (a damaged gz stream fails here too).
        if (!in.checkEOF())
        {
            fail(Kind::Corrupted, "", "unreadable (damaged compressed stream?)");
        }
        return false;
    }
    catch (const std::bad_alloc&)
    {
        fail(Kind::Corrupted, "", "a corrupted size asked for more memory than exists");
        return false;
    }
    catch (const std::exception& e)
    {
        const std::string what = mrpt::exception_to_str(e);
        if (auto cls = unregisteredClass(what); !cls.empty())
        {
            fail(Kind::UnknownClass, cls, "");
        }
        else
        {
            fail(in.checkEOF() ? Kind::Truncated : Kind::Corrupted, "", innermostMessage(what));
        }
        return false;
    }
    if (!obj)
    {
        fail(Kind::Corrupted, "", "a null object");
        return false;
    }
    return true;
}

mrpt::serialization::CSerializable::Ptr RawlogReader::next()
{
    if (m_whole)
    {
        if (m_wholeNext < m_whole->size())
        {
            m_entry++;
            return m_whole->getAsGeneric(m_wholeNext++);
        }
        return nullptr;
    }
    mrpt::serialization::CSerializable::Ptr obj;
    if (m_ended || !readObject(obj))
    {
        m_ended = true;
        return nullptr;
    }
    if (const auto whole = std::dynamic_pointer_cast<mrpt::obs::CRawlog>(obj))
    {
        m_ended = true;  // the whole rawlog as one object (MRPT's other format)
        m_whole.emplace();
        m_whole->swap(*whole);
        return next();
    }
    if (const auto comment = std::dynamic_pointer_cast<mrpt::obs::CObservationComment>(obj))
    {
        m_comment += (m_comment.empty() ? "" : "\n") + comment->text;  // not an entry
        return next();
    }
    if (!isRawlogEntry(*obj))
    {
        m_defect =
            TDefect{Kind::NotAnEntry, m_entry, m_byte, obj->GetRuntimeClass()->className, ""};
        m_ended = true;
        return nullptr;
    }
    m_entry++;
    return obj;
}

RawlogReader::TResult RawlogReader::Read(const std::string& path)
{
    RawlogReader reader(path);
    TResult res;
    res.path = path;
    while (const auto obj = reader.next())
    {
        res.rawlog.insert(obj);
    }
    res.rawlog.setCommentText(reader.comment());
    res.defect = reader.defect();
    return res;
}

bool RawlogReader::IsSemlocRawlog(const std::string& path)
{
    try
    {
        RawlogReader reader(path);
        mrpt::serialization::CSerializable::Ptr first;
        if (!reader.readObject(first))
        {
            return false;
        }
        const auto comment = std::dynamic_pointer_cast<mrpt::obs::CObservationComment>(first);
        return comment && comment->text.rfind(kRawlogSignature, 0) == 0;
    }
    catch (const std::exception&)
    {
        return false;
    }
}

mrpt::obs::CRawlog RawlogReader::Load(const std::string& path)
{
    TResult r = Read(path);
    if (r.defect)
    {
        THROW_EXCEPTION(r.defectMessage());
    }
    if (r.rawlog.empty())
    {
        THROW_EXCEPTION("rawlog '" + path + "' holds no entries");
    }
    return r.rawlog;
}

std::string RawlogReader::TResult::defectMessage() const
{
    if (!defect)
    {
        return "";
    }
    const auto& d = *defect;
    const std::string where = mrpt::format("entry %zu (byte %llu of the uncompressed stream)",
                                           d.entry, static_cast<unsigned long long>(d.byte));
    std::string m = "rawlog '" + path + "': ";
    switch (d.kind)
    {
        case Kind::Truncated:
            m += "truncated: the file ends inside " + where;
            break;
        case Kind::Corrupted:
            m += where + " is corrupted: " + d.detail;
            break;
        case Kind::UnknownClass:
            m += where + " holds an object of unknown class '" + d.className +
                 "' (written with a library semloc does not load?)";
            break;
        case Kind::NotAnEntry:
            m += where + " is a '" + d.className +
                 "', not an observation, sensory frame or action collection";
            break;
    }
    m += d.entry == 0   ? "; no entry before it is intact"
         : d.entry == 1 ? "; entry 0 before it is intact"
                        : mrpt::format("; entries 0-%zu before it are intact", d.entry - 1);
    return m;
}

}  // namespace semloc
