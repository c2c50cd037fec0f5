#pragma once
// What a node needs in memory at a domain, known before anything is allocated, so a request far beyond the
// machine fails at once with the node and the bytes named (instead of std::bad_alloc or swapping later).
//
// The estimate counts the node's outputs at the request's sample count (a heightfield 4 bytes a sample,
// an image 16, a mesh about 160 for its vertices, faces and attributes, other values 4) plus one working
// field of 4 bytes a sample, plus what the node type itself declares it needs beyond that (NodeType::
// extra_bytes: images of more than four channels, words grown by rewriting, files read whole, values sized
// by their inputs). It is a floor, not a ceiling: a node may need more.
#include <cstdint>
#include <string>

#include "graph/cost_query.h"
#include "graph/domain.h"
#include "graph/node_type.h"

namespace orogen {

// The outputs by type and one working field at the domain's sample count.
std::uint64_t estimate_output_bytes(const NodeType& type, const Domain& domain);
// estimate_output_bytes plus the type's extra_bytes for the query's parameters and inputs (saturating).
// A node type's extra_bytes that throws (a file it cannot read yet, say) adds nothing: the node reports
// that itself when it runs.
std::uint64_t estimate_node_bytes(const CostQuery& query);

// "node type Blur needs at least 17.2 GB at 65536x65536 samples; the memory limit is 7.8 GB (--max-memory)"
std::string memory_refusal(const NodeType& type, const Domain& domain, std::uint64_t need, std::uint64_t limit);

// The memory this machine can give a process now (MemAvailable of /proc/meminfo), or 0 if unknown.
std::uint64_t available_memory_bytes();

// "17.2 GB", "512 MB", "4.0 KB"
std::string format_bytes(std::uint64_t bytes);

}  // namespace orogen
