// The streaming reader: feeds every chunk to the binary and the ASCII parser side by side
// and applies the detection rule when the input ends (or when both parsers are dead).
#include "ascii_parser.h"
#include "binary_parser.h"

namespace stltopo {

using detail::AsciiParser;
using detail::BinaryParser;
using detail::Builder;
using detail::format;
using detail::oom;

// The state of one read: both parsers (either is deleted once it is dead and can no longer
// be the answer), the byte count and the sticky status.
struct Reader::Impl {
  ReadOptions opt;
  BinaryParser* bin = nullptr;
  AsciiParser* ascii = nullptr;
  uint64_t total = 0;
  Status sticky;
  bool finished = false;

  explicit Impl(const ReadOptions& o) : opt(o) { start(); }
  ~Impl() { clear(); }
  void clear() {
    detail::tryDelete(bin);
    bin = nullptr;
    detail::tryDelete(ascii);
    ascii = nullptr;
  }
  void start() {
    clear();
    bin = detail::tryNew<BinaryParser>(opt);
    ascii = detail::tryNew<AsciiParser>(opt);
    total = 0;
    sticky = Status{};
    finished = false;
    if (!bin || !ascii || !ascii->reserveBuffers()) {
      clear();
      sticky = oom("the reader");
    }
  }

  bool binaryDead() const { return bin == nullptr || bin->b.failed(); }
  bool asciiDead() const { return ascii == nullptr || ascii->dead(); }

  // The detection rule. atEnd: all input has arrived.
  Status decide(bool atEnd, Mesh* out) {
    Status bs;
    BinaryParser::End be = BinaryParser::End::Error;
    if (bin) {
      if (atEnd)
        be = bin->end(bs);
      else
        bs = bin->b.error;
    }
    // The first token may still be pending at the end ("solid" and nothing else).
    if (atEnd && ascii && !ascii->decided && ascii->inToken && !ascii->dead()) ascii->endCarry();
    bool solidFile = ascii && ascii->decided && ascii->isSolid;
    auto takeBinary = [&](bool trailing) -> Status {
      if (trailing) {
        uint64_t extra = bin->offset - bin->partStart;
        bin->b.addWarning(Code::TrailingBytes,
                          format("%llu extra byte%s after the last triangle at offset %llu were ignored",
                                 (unsigned long long)extra, extra == 1 ? "" : "s", (unsigned long long)bin->partStart),
                          bin->partStart);
      }
      bin->b.mesh.format = Format::Binary;
      return finishBuilder(bin->b, out);
    };
    if (atEnd && be == BinaryParser::End::Exact) return takeBinary(false);
    if (solidFile) {
      Status as = atEnd ? ascii->end() : ascii->b.error;
      if (as.ok()) {
        ascii->b.mesh.format = Format::Ascii;
        return finishBuilder(ascii->b, out);
      }
      if (atEnd && be == BinaryParser::End::Trailing) return takeBinary(true);
      if (ascii->binaryLooking && !bs.ok()) return bs;
      return as;
    }
    if (atEnd && total == 0) return Status::error(Code::Empty, "the file is empty (0 bytes)", 0);
    if (atEnd && be == BinaryParser::End::TooShort)
      return Status::error(Code::NotStl,
                           format("the file has %llu bytes: too short for a binary STL (84-byte minimum) and it does "
                                  "not start with 'solid'",
                                  (unsigned long long)total),
                           0);
    if (atEnd && be == BinaryParser::End::Trailing) return takeBinary(true);
    return bs;
  }

  Status finishBuilder(Builder& b, Mesh* out) {
    if (b.failed()) return b.error;  // a warning could not be stored
    b.endSolid();
    if (!b.decodeColors()) return oom("the colour array");
    b.releaseWeld();
    if (out) *out = std::move(b.mesh);
    return Status{};
  }
};

namespace {
Status noReader() { return oom("the reader"); }
}  // namespace

Reader::Reader(const ReadOptions& options) : impl_(detail::tryNew<Impl>(options)) {}
Reader::~Reader() { detail::tryDelete(impl_); }
uint64_t Reader::bytesRead() const { return impl_ ? impl_->total : 0; }
void Reader::reset() {
  if (impl_) impl_->start();
}

Status Reader::feed(const uint8_t* data, size_t size) {
  if (!impl_) return noReader();
  Impl& m = *impl_;
  if (m.finished) return Status::error(Code::InvalidArgument, "feed() after finish(); call reset() first");
  if (!m.sticky.ok()) return m.sticky;
  if (m.opt.maxBytes && m.total + size > m.opt.maxBytes) {
    m.sticky = Status::error(Code::TooLarge,
                             format("the input is larger than maxBytes (%llu)", (unsigned long long)m.opt.maxBytes),
                             m.opt.maxBytes);
    m.clear();
    return m.sticky;
  }
  m.total += size;
  if (!m.binaryDead()) {
    m.bin->feed(data, size);
    if (m.bin->b.failed()) m.bin->b.dropArrays();  // keep its status
  }
  if (!m.asciiDead()) {
    m.ascii->feed(data, size);
    if (m.asciiDead() && m.ascii->decided && !m.ascii->isSolid) {
      detail::tryDelete(m.ascii);  // not an ASCII file: free it now
      m.ascii = nullptr;
    }
  }
  if (m.binaryDead() && m.asciiDead()) {
    m.sticky = m.decide(false, nullptr);
    if (m.sticky.ok()) m.sticky = Status::error(Code::NotStl, "the input is not STL");
    m.clear();
    return m.sticky;
  }
  return Status{};
}

Status Reader::finish(Mesh& out) {
  if (!impl_) return noReader();
  Impl& m = *impl_;
  if (m.finished) return Status::error(Code::InvalidArgument, "finish() called twice; call reset() first");
  m.finished = true;
  if (!m.sticky.ok()) return m.sticky;
  Status s = m.decide(true, &out);
  m.clear();
  if (!s.ok()) m.sticky = s;
  return s;
}

Status readStl(const uint8_t* data, size_t size, Mesh& out, const ReadOptions& options) {
  ReadOptions o = options;
  if (o.sizeHint == 0) o.sizeHint = size;
  Reader r(o);
  Status s = r.feed(data, size);
  if (!s.ok()) return s;
  return r.finish(out);
}

}  // namespace stltopo
