/* semloc — RawlogReader: a rawlog entry by entry, every early stop located. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/io/RawlogReader.h>

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

RawlogReader::TResult RawlogReader::Read(const std::string& path)
{
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
    {
        THROW_EXCEPTION("rawlog '" + path + "' does not exist");
    }
    if (std::filesystem::is_directory(path, ec))
    {
        THROW_EXCEPTION("rawlog '" + path + "' is a directory, not a file");
    }
    mrpt::io::CFileGZInputStream in;
    std::string why;
    if (!in.open(path, why))
    {
        THROW_EXCEPTION("cannot open rawlog '" + path + "': " + why);
    }
    auto arch = mrpt::serialization::archiveFrom(in);

    TResult res;
    res.path = path;
    for (size_t entry = 0;; entry++)
    {
        const uint64_t byte = in.getPosition();
        auto fail = [&](Kind kind, std::string className, std::string detail) {
            res.defect = TDefect{kind, entry, byte, std::move(className), std::move(detail)};
        };
        mrpt::serialization::CSerializable::Ptr obj;
        try
        {
            obj = arch.ReadObject();
        }
        catch (const mrpt::serialization::CExceptionEOF&)
        {
            // CArchive throws this when the entry's first byte cannot be read: a clean end
            // only if the stream really is at its end (a damaged gz stream fails here too).
            if (!in.checkEOF())
            {
                fail(Kind::Corrupted, "", "unreadable (damaged compressed stream?)");
            }
            break;
        }
        catch (const std::bad_alloc&)
        {
            fail(Kind::Corrupted, "", "a corrupted size asked for more memory than exists");
            break;
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
            break;
        }
        if (!obj)
        {
            fail(Kind::Corrupted, "", "a null object");
            break;
        }
        if (const auto whole = std::dynamic_pointer_cast<mrpt::obs::CRawlog>(obj))
        {
            res.rawlog.swap(*whole);  // the whole rawlog as one object (MRPT's other format)
            break;
        }
        if (!isRawlogEntry(*obj))
        {
            fail(Kind::NotAnEntry, obj->GetRuntimeClass()->className, "");
            break;
        }
        res.rawlog.insert(obj);
    }
    return res;
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
