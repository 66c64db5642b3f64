// tinygltf's file callbacks over a fileio::FileSource: every file a glTF loader opens beyond the
// bytes it is given (a .gltf's external buffers and images) is read through the source: the one
// checked reader of the disk, or a stage's declared inputs (StageContext::files()). tinygltf's
// own FileExists fopen()s the path, which blocks on a FIFO, and its reader sizes its buffer from
// tellg(), which is -1 for a directory.
#pragma once

#include <tiny_gltf.h>

#include "libs/fileio/file_source.h"

namespace sylva::gltf {

// Callbacks reading through `files`, which must outlive every load that uses them. A file that
// cannot be read adds "<path>: error: <reason>" as a line to tinygltf's error text.
tinygltf::FsCallbacks file_callbacks(const fileio::FileSource& files);

}  // namespace sylva::gltf
