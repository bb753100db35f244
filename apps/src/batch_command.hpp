#pragma once
#include <string>
#include <vector>

namespace invfem::app {

// `invfem batch SCENE... --out DIR [--jobs N] [--quick] [--shard I/N] [--mp4]`.
int batch_command(const std::vector<std::string>& args, const std::string& self_exe);
extern const char* const kBatchHelp;

}  // namespace invfem::app
