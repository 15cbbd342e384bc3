#include "binary_parser.h"

namespace stltopo::detail {

inline void BinaryParser::startPart() {
  uint32_t n;
  std::memcpy(&n, header + 80, 4);
  if constexpr (std::endian::native == std::endian::big) n = __builtin_bswap32(n);
  partCount = n;
  partDone = 0;
  partFirst = b.mesh.nTriangles();
  ++partIndex;
  size_t len = 0;
  while (len < 80 && header[len] != 0) ++len;
  const char* nameBegin = reinterpret_cast<const char*>(header);
  const char* nameEnd = nameBegin + len;
  trim(nameBegin, nameEnd);
  PartColor pc;
  static const char kColor[] = "COLOR=";
  for (size_t i = 0; i + 6 + 4 <= 80; ++i) {
    if (std::memcmp(header + i, kColor, 6) == 0) {
      pc.magics = true;
      pc.rgb[0] = header[i + 6];
      pc.rgb[1] = header[i + 7];
      pc.rgb[2] = header[i + 8];
      break;
    }
  }
  if (!b.beginSolid(nameBegin, size_t(nameEnd - nameBegin), &pc)) return;
  uint64_t total = uint64_t(b.mesh.nTriangles()) + n;
  if (total > b.opt.maxTriangles) {
    skipping = true;
    skipNeeded = kHeaderBytes + kRecordBytes * uint64_t(n);
    return;
  }
  // Reserve only what the known input size can hold.
  if (b.opt.sizeHint > partStart + kHeaderBytes) {
    uint64_t fits = (b.opt.sizeHint - partStart - kHeaderBytes) / kRecordBytes;
    b.reserveTriangles(uint64_t(b.mesh.nTriangles()) + std::min<uint64_t>(n, fits));
  }
  inRecords = n > 0;
  if (!inRecords) finishPart();
}

inline void BinaryParser::finishPart() {
  b.endSolid();
  inRecords = false;
  headerHave = 0;
  partStart = offset;
}

void BinaryParser::feed(const uint8_t* p, size_t n) {
  size_t i = 0;
  while (i < n && !b.failed()) {
    if (skipping) {
      uint64_t have = offset - partStart;
      uint64_t take = std::min<uint64_t>(n - i, skipNeeded > have ? skipNeeded - have : 0);
      if (take == 0) take = n - i;  // beyond: the outcome (too-large) is known; just count
      offset += take;
      i += size_t(take);
      continue;
    }
    if (!inRecords) {
      uint32_t take = uint32_t(std::min<size_t>(kHeaderBytes - headerHave, n - i));
      std::memcpy(header + headerHave, p + i, take);
      headerHave += take;
      i += take;
      offset += take;
      if (headerHave == kHeaderBytes) startPart();
      continue;
    }
    if (recHave > 0) {
      uint32_t take = uint32_t(std::min<size_t>(kRecordBytes - recHave, n - i));
      std::memcpy(rec + recHave, p + i, take);
      recHave += take;
      i += take;
      offset += take;
      if (recHave == kRecordBytes) {
        recHave = 0;
        record(rec, offset - kRecordBytes);
        if (skipping) continue;
        if (++partDone == partCount) finishPart();
      }
      continue;
    }
    // Fast path: whole records straight from the input.
    uint64_t left = uint64_t(partCount - partDone);
    uint64_t whole = std::min<uint64_t>(left, (n - i) / kRecordBytes);
    constexpr uint64_t kBatch = Builder::kBatchRecords;
    bool hashed = false;
    uint64_t k = 0;
#if STLTOPO_THREADS
    // Threaded: batches of whole records, with the mesh of one at a time (below), which adds
    // whatever a batch leaves (see addBatchParallel). Only in a part of at least 2 x 65536
    // records: the threads' private weld arrays are about 46 B a record of fresh memory,
    // which in a smaller file cost more than the second thread saves.
    if (threads > 1 && partCount >= 2 * parallelGrain(65536)) {
      while (whole - k >= 2 * parallelGrain(4096)) {
        const uint32_t count = uint32_t(std::min<uint64_t>(b.parallelBatchRecords(), whole - k));
        const uint64_t done = b.addBatchParallel(p + i, count, offset, threads);
        i += size_t(done) * kRecordBytes;
        offset += done * kRecordBytes;
        partDone += uint32_t(done);
        k += done;
        if (b.failed()) {
          addFailed();
          break;
        }
        if (done < count) break;
      }
    }
#endif
    for (uint64_t k0 = k; k < whole && !skipping; ++k) {
      if ((k - k0) % kBatch == 0) {
        hashed = !b.table.empty();
        if (hashed) b.prepareBatch(p + i, uint32_t(std::min<uint64_t>(kBatch, whole - k)));
      }
      record(p + i, offset, hashed ? b.batchHash + 3 * ((k - k0) % kBatch) : nullptr);
      i += kRecordBytes;
      offset += kRecordBytes;
      ++partDone;
    }
    if (skipping) continue;
    if (partDone == partCount) {
      finishPart();
      continue;
    }
    if (i < n) {
      uint32_t take = uint32_t(n - i);  // < 50
      std::memcpy(rec, p + i, take);
      recHave = take;
      i += take;
      offset += take;
    }
  }
}

BinaryParser::End BinaryParser::end(Status& st) {
  if (b.failed()) {
    st = b.error;
    return End::Error;
  }
  if (partIndex == 0) return End::TooShort;  // < 84 bytes: no header at all
  if (skipping) {
    uint64_t needBytes = partStart + skipNeeded;
    if (offset < needBytes) {
      st = truncated(needBytes);
    } else if (!contentError.ok()) {
      st = contentError;
    } else {
      st = Status::error(
          Code::TooLarge,
          format("the header promises %u triangles, more than maxTriangles (%u)", partCount, b.opt.maxTriangles),
          partStart + 80);
    }
    return End::Error;
  }
  if (inRecords) {
    st = truncated(partStart + kHeaderBytes + kRecordBytes * uint64_t(partCount));
    return End::Error;
  }
  if (headerHave > 0) return End::Trailing;  // < 84 bytes after the last part
  return End::Exact;
}

inline Status BinaryParser::truncated(uint64_t needBytes) {
  // The first incomplete triangle: triangles before this part plus the complete records.
  uint64_t body = offset - partStart > kHeaderBytes ? offset - partStart - kHeaderBytes : 0;
  uint32_t tri = uint32_t(std::min<uint64_t>(partFirst + body / kRecordBytes, kInvalid - 1));
  std::string part = partIndex > 1
                         ? format("part %u (header at offset %llu): ", partIndex, (unsigned long long)partStart)
                         : std::string();
  return Status::error(Code::Truncated,
                       format("%sthe header promises %u triangles (%llu bytes) but the file has %llu bytes; "
                              "data stops at offset %llu, inside triangle %u",
                              part.c_str(), partCount, (unsigned long long)needBytes, (unsigned long long)offset,
                              (unsigned long long)offset, tri),
                       offset, 0, tri);
}

}  // namespace stltopo::detail
