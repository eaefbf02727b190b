/* semloc — a rawlog read entry by entry, so that a clean end, a truncated file and a
 * corrupted entry are told apart and located. */
#pragma once

#include <mrpt/obs/CRawlog.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace semloc
{
/** Reads an MRPT rawlog (gz-compressed or not) one top-level entry at a time.
 *
 *  MRPT's CRawlog::loadFromRawLogFile prints the exception of a bad entry and returns the
 *  entries read so far, so a truncated or corrupted dataset looks like a shorter one. This
 *  reader stops at the same place but says where and why (TDefect): the caller refuses the
 *  file or, when told to, uses the intact entries before the bad one.
 *
 *  Entries are counted from 0 in file order; a CObservationComment is not an entry: its text
 *  becomes the rawlog's comment text (every rawlog semloc writes begins with one). A file holding
 * one serialized CRawlog object is read as that rawlog.
 *
 *  An object of the class streams the entries (next()): memory does not grow with the file's
 *  length; Read() and Load() hold the whole rawlog. */
class RawlogReader
{
public:
    /** Why reading stopped before the end of the file. */
    struct TDefect
    {
        /** What was wrong with the entry. */
        enum class Kind
        {
            /** The file ends inside the entry. */
            Truncated,
            /** The entry's bytes do not deserialize (or the compressed stream is damaged). */
            Corrupted,
            /** The entry (or an object inside it) has a class MRPT does not know. */
            UnknownClass,
            /** A known class that is not an observation, sensory frame or action collection. */
            NotAnEntry
        };
        /** What was wrong. */
        Kind kind = Kind::Corrupted;
        /** Index of the bad entry = number of intact entries before it. */
        size_t entry = 0;
        /** Offset of the entry's first byte in the uncompressed stream. */
        uint64_t byte = 0;
        /** The class involved, when known (UnknownClass, NotAnEntry). */
        std::string className;
        /** MRPT's innermost message (Corrupted). */
        std::string detail;
    };

    /** A rawlog and, if reading stopped early, why. */
    struct TResult
    {
        /** The path read. */
        std::string path;
        /** The intact entries (all of them when `defect` is empty). */
        mrpt::obs::CRawlog rawlog;
        /** Set when an entry could not be read; the entries from it on are missing. */
        std::optional<TDefect> defect;

        /** "rawlog 'p': the file ends inside entry 57 (byte 123 of the uncompressed
         *  stream): truncated; entries 0-56 are intact", or "" without a defect. */
        std::string defectMessage() const;
    };

    /** Opens `path`. Throws (naming the path) when the file cannot be opened: missing, a
     *  directory, unreadable. */
    explicit RawlogReader(const std::string& path);
    ~RawlogReader();
    RawlogReader(const RawlogReader&) = delete;
    RawlogReader& operator=(const RawlogReader&) = delete;

    /** The next entry (an observation, sensory frame or action collection); null at the end
     *  of the file or at a bad entry, which defect() then describes. */
    mrpt::serialization::CSerializable::Ptr next();
    /** Why next() stopped before the end of the file, if it did. */
    const std::optional<TDefect>& defect() const { return m_defect; }
    /** The text of the comments (CObservationComment) read so far, joined by newlines: they
     *  are the rawlog's comment, not entries. */
    const std::string& comment() const { return m_comment; }
    /** Entries next() returned so far. */
    size_t entriesRead() const { return m_entry; }
    /** The path read. */
    const std::string& path() const { return m_path; }

    /** Reads every entry it can. Throws (naming the path) only when the file cannot be
     *  opened: missing, a directory, unreadable. */
    static TResult Read(const std::string& path);

    /** Reads the whole rawlog; throws TResult::defectMessage() on any defect and an error
     *  on a file without entries. */
    static mrpt::obs::CRawlog Load(const std::string& path);

    /** True when the file at `path` is a rawlog semloc wrote: its first entry is a comment
     *  that starts with kRawlogSignature (RawlogWriter.h). Reads that entry only. */
    static bool IsSemlocRawlog(const std::string& path);

private:
    /** Reads the next object of the stream into `obj`; false (and m_defect set) at a bad
     *  one or the end. */
    bool readObject(mrpt::serialization::CSerializable::Ptr& obj);

    struct TStream;
    std::string m_path;
    std::unique_ptr<TStream> m_stream;
    std::optional<TDefect> m_defect;
    size_t m_entry = 0;
    std::string m_comment;
    /** Offset of the last object read in the uncompressed stream. */
    uint64_t m_byte = 0;
    /** A file holding one whole CRawlog object: its entries, and the next one's index. */
    std::optional<mrpt::obs::CRawlog> m_whole;
    size_t m_wholeNext = 0;
    bool m_ended = false;
};

}  // namespace semloc
