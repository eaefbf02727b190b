/* semloc — world text read and written in pieces (private): the reader on any source, the
 * writer as a source, so that neither a file's nor a world's whole text, nor a tree of YAML
 * nodes for its objects, is ever held in memory. */
#pragma once

#include <semloc/world/World.h>

#include <cstddef>
#include <fstream>
#include <functional>
#include <memory>
#include <string>

namespace semloc::detail
{
/** Text read in pieces, from its start again after rewind(). */
class TextSource
{
public:
    virtual ~TextSource() = default;
    /** Up to `n` bytes into `buf`: how many (0 at the end). Throws on a read error. */
    virtual size_t read(char* buf, size_t n) = 0;
    /** Reading starts again from the first byte. */
    virtual void rewind() = 0;
};

/** A string's bytes (the string must outlive the source). */
class StringSource : public TextSource
{
public:
    explicit StringSource(const std::string& text) : m_text(text) {}
    size_t read(char* buf, size_t n) override;
    void rewind() override { m_at = 0; }

private:
    const std::string& m_text;
    size_t m_at = 0;
};

/** A file's bytes. Throws "world file 'PATH': cannot open for reading" if it cannot be
 *  opened, "world file 'PATH': read error" when reading fails. */
class FileSource : public TextSource
{
public:
    explicit FileSource(const std::string& path);
    size_t read(char* buf, size_t n) override;
    void rewind() override;

private:
    std::string m_path;
    std::ifstream m_file;
};

/** World::toYamlText() of a world (which must outlive the source), made line by line as it
 *  is read; with `objects` (which must outlive it too), of the world with those objects. */
class WorldTextSource : public TextSource
{
public:
    explicit WorldTextSource(const World& world, const WorldObjectList* objects = nullptr)
        : m_world(world), m_objects(objects)
    {
    }
    size_t read(char* buf, size_t n) override;
    void rewind() override;

private:
    /** The next line(s) into m_line; false at the end of the text. */
    bool nextLines();

    /** Objects in the text. */
    size_t objectCount() const;

    const World& m_world;
    const WorldObjectList* m_objects = nullptr;
    int m_part = 0;     // 0 header, 1 objects, 2 beacons, 3 trajectory, 4 done
    size_t m_item = 0;  // the next object or beacon
    std::string m_line;
    size_t m_at = 0;  // bytes of m_line already read
};

/** 1-based line of the first byte sequence of `source` that is not UTF-8 (overlong forms and
 *  surrogates are not told apart), or 0 if there is none; the source is read to its end
 *  either way (a read error is one). YAML text must be Unicode, and libfyaml (MRPT's YAML
 *  parser) loops forever on some invalid bytes (found by tests/fuzz/fuzz_world). */
size_t firstNonUtf8Line(TextSource& source);

/** Receives each object of a world text, read and checked, in file order (its index), in
 *  place of World::objects. */
using ObjectSink = std::function<void(WorldObject&& object, size_t index)>;

/** World::FromText() on the text of `source`: every check and message the same (the UTF-8
 *  check reads the source once through, then it is parsed from its start). The objects and
 *  beacons are parsed one by one as the parser reads them. With `sink`, each object goes to
 *  it instead of World::objects (what the checks need of them is kept: ids, shapes,
 *  centres); a world text with a trajectory is then refused (its check needs the objects). */
World readWorld(TextSource& source, const std::string& sourceName,
                const ObjectSink* sink = nullptr);

/** Reads back World::toYamlText() of `world` (with `objects` as its objects if given) as
 *  `sourceName` (streamed: memory about 40 bytes an object beyond the world itself, but for
 *  a world with a trajectory, read back whole). Throws the reader's error ("world file
 *  'NAME': ...") if it does not load, "it reads back as another world" if it loads with
 *  another name, other objects (count, ids, labels, shapes) or other beacons (count, ids). */
void checkReadsBack(const World& world, const std::string& sourceName,
                    const WorldObjectList* objects = nullptr);
}  // namespace semloc::detail
