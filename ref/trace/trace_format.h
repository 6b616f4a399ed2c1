// Binary layout constants of trace.dtr, shared by the writer and the reader.
// The layout is specified byte by byte in ref/trace/README.md (schema version kSchemaVersion).
#pragma once
#include <cstdint>

namespace dynref::trace::format {

constexpr char kMagic[8] = {'D', 'Y', 'N', 'T', 'R', 'A', 'C', 'E'};       // file start
constexpr char kEndMagic[8] = {'D', 'Y', 'N', 'T', 'R', 'E', 'N', 'D'};    // last 8 bytes
constexpr int kPreambleSize = 16;  // magic(8) + u32 schema version + u8 level + 3 zero bytes
constexpr int kTrailerSize = 16;   // u64 footer offset + end magic(8)

// Record tags (first byte of every body record).
enum Tag : uint8_t {
  kTagString = 0x01,    // string-table definition: varint id, str
  kTagFrame = 0x02,     // BeginFrame
  kTagPose = 0x03,      // FramePose
  kTagCount = 0x04,     // FrameCount
  kTagObs = 0x05,       // Observation
  kTagProb = 0x06,      // ProbabilityUpdate
  kTagResidual = 0x07,  // Residual
  kTagDecision = 0x08,  // Decision
  kTagFooter = 0x7F,    // start of the footer
};

}  // namespace dynref::trace::format
