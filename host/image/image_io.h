// Image files: PNG through stb_image_write, PFM for float AOVs, and glref's
// binary primitive-id format so that ../shared/tools/glref/ids_tool.py reads ours.
// Every writer writes atomically (host/image/safe_output.h): the file at the
// path is replaced only by a complete one.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rast {

class AtomicFile;

// Into an open AtomicFile, which the caller commits (several outputs of one
// run are all written before any is renamed into place).
// alpha: RGBA (straight alpha, the top byte), else RGB.
void writePng(AtomicFile& f, int w, int h, const std::vector<uint32_t>& rgba, bool alpha = false);
void writePfm(AtomicFile& f, int w, int h, int channels, const float* data);
void writeIdsBin(AtomicFile& f, int w, int h, const std::vector<uint32_t>& idsBottomUp);
void writeNpy(AtomicFile& f, int w, int h, int channels, const char* descr, const void* bottomUp);

// Each to its own file, committed. rgba: R in the low byte, top row first.
void writePng(const std::string& path, int w, int h, const std::vector<uint32_t>& rgba);
// Greyscale (channels 1) or colour (3) PFM; data bottom row first, as PFM stores it.
void writePfm(const std::string& path, int w, int h, int channels, const float* data);
// "glref-ids W H u32le top-down\n" then W*H little-endian u32, top row first.
// ids come bottom row first (as rendered) and are flipped here.
void writeIdsBin(const std::string& path, int w, int h, const std::vector<uint32_t>& idsBottomUp);
// NumPy's .npy (format 1.0, little-endian, C order) of an image given bottom row
// first, written top row first as numpy users index images: [h][w] or
// [h][w][channels]. descr: "<f4" (float) or "<u4" (uint32); 4-byte elements.
void writeNpy(const std::string& path, int w, int h, int channels, const char* descr, const void* bottomUp);

// Readers (tests and tools). Each returns data in its file's row order.
std::vector<uint32_t> readIdsBin(const std::string& path, int& w, int& h);  // top row first
std::vector<float> readPfm(const std::string& path, int& w, int& h, int& channels);  // bottom row first
std::vector<uint32_t> readPng(const std::string& path, int& w, int& h);  // RGBA8, top row first

}  // namespace rast
