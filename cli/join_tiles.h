#pragma once
// The vector half of `--merge` (cli/merge_tiles.h): the tiles' points and curves files joined into one file of
// the same format, streamed line by line (a tile's file is never held whole).
//
// - Points (CSV, ASCII PLY): every tile's points in tile order, under one header; a point written by two tiles
//   (one lying exactly on the line of samples they share) is kept once. The tiles must have the same columns.
// - Curves (GeoJSON-like JSON, OBJ lines): every tile's curves in tile order, renumbered (`index`, `parent`,
//   OBJ groups and vertex numbers) so that each parent still names its curve. A curve cut by a tile border
//   stays two curves: joining rivers into one network is RiverExtract's work across tiles.
#include <filesystem>
#include <vector>

namespace orogen::cli {

// Joins `tiles` (in tile order) into `target`. `border_x` and `border_y` are the coordinates (metres) of the
// lines of samples neighboring tiles share: only points on them can be in two tiles. Throws
// std::runtime_error naming the tile that cannot be read or does not match the first one.
void join_points_csv(const std::vector<std::filesystem::path>& tiles, const std::filesystem::path& target,
                     const std::vector<double>& border_x, const std::vector<double>& border_y);
void join_points_ply(const std::vector<std::filesystem::path>& tiles, const std::filesystem::path& target,
                     const std::vector<double>& border_x, const std::vector<double>& border_y);
void join_curves_json(const std::vector<std::filesystem::path>& tiles, const std::filesystem::path& target);
void join_curves_obj(const std::vector<std::filesystem::path>& tiles, const std::filesystem::path& target);

}  // namespace orogen::cli
