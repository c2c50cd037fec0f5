"""Writes the seed graphs graphs/voronoi_island.json (S. Weiss 2015), graphs/forest.json (L. Potter 2017) and
completes graphs/rural_resources.json (H. Long 2016) after scripts/make_climate_graphs.py has written its base
(run from anywhere; it runs make_climate_graphs.py first).

voronoi_island.json and forest.json were since rewritten to use the subgraph library (assets island and
forest_cover, docs/subgraphs.md) with byte-identical outputs; this script writes their plain form, kept as
tests/fixtures/before_library/, which tests/test_library_rewrites.cpp compares them with. After regenerating,
rebuild the rewrite with `orogen subgraph extract` or copy the result over that fixture."""
import json
import os
import runpy

HERE = os.path.dirname(os.path.abspath(__file__))
GRAPHS = os.path.join(HERE, "..", "graphs")
runpy.run_path(os.path.join(HERE, "make_climate_graphs.py"))


def make_adder(nodes):
    def N(id, type, inputs=None, **params):
        n = {"id": id, "type": type}
        if inputs:
            n["inputs"] = inputs
        if params:
            n["params"] = params
        nodes.append(n)
        return n
    return N


def add_meshes(N):
    """The instance meshes: SeamScape's green tree, a conifer, ABOP's bush (L-systems) and a hull rock."""
    N("tree", "LSystem", None, axiom="T(140,90,40,100)",
      rules="// SeamScape's green tree (S. Ekman et al. 2016, a Chalmers bachelor thesis, Appendix A, corrected: X ~ U(-30, 30) degrees)\nT(r,g,b,a) -> #(r,g,b)>F(0.5,1)[T(r,g,b,0.99*a)][+(60+U(-30,30))T(r,g,b,0.99*a)][-(60+U(-30,30))T(r,g,b,0.99*a)][&(60+U(-30,30))T(r,g,b,0.99*a)][^(60+U(-30,30))T(r,g,b,0.99*a)] : 75\nF(d,n) -> F(1.7*d,n)>\nT(r,g,b,a) : a < 98 -> F(0.8,1)L(1.2,40,140+U(-30,30),40) : 25",
      iterations=5, seed=7)
    N("tree_turtle", "Turtle3D", {"in": "tree.out"}, width=0.9, width_factor=0.8, tropism_strength=0.05, angle=25)
    N("tree_mesh", "TreeMesh", {"in": "tree_turtle.out", "leaves": "tree_turtle.leaves"}, sides=5, max_triangles=2500)
    N("conifer", "LSystem", None, axiom="FFFA", rules="A -> !(0.7)[&(60)F(2)L(1.5,20,70,30)]/(137)[&(60)F(2)L(1.5,20,70,30)]/(137)[&(60)F(2)L(1.5,20,70,30)]F(1.2)A\nF(l) -> F(l*0.95)", iterations=8)
    N("conifer_turtle", "Turtle3D", {"in": "conifer.out"}, step=1.2, width=0.5, width_factor=0.9, angle=25)
    N("conifer_mesh", "TreeMesh", {"in": "conifer_turtle.out", "leaves": "conifer_turtle.leaves"}, sides=5, max_triangles=1200)
    N("bush", "LSystem", None, axiom="!(0.25)A", rules="// ABOP Fig. 1.25 (without the polygon leaves' shape): a 3D bush\nA -> [&FL!A]/////[&FL!A]///////[&FL!A]\nF -> S/////F\nS -> FL", iterations=5)
    N("bush_turtle", "Turtle3D", {"in": "bush.out"}, angle=22.5, step=0.3, width=0.25, width_factor=0.72, leaf_size=0.3)
    N("bush_mesh", "TreeMesh", {"in": "bush_turtle.out", "leaves": "bush_turtle.leaves"}, sides=4, max_triangles=600)
    N("rock", "HullRock", None, points=20, radii=[1.6, 1.1, 0.8], sigma=0.1, seed=3)


# --- Weiss 2015: the Voronoi island, eroded, with biomes and vegetation ---
island = {"format": "orogen-graph", "version": 4, "domain": {"size": [4096, 4096], "resolution": [256, 256]},
          "nodes": [{"id": "island", "type": "VoronoiIsland", "params": {"cells": 4000, "distribution": "poisson", "relaxation": 2, "shape_scale": 1.1, "shape_offset": -0.3, "max_elevation": 900, "ocean_depth": 150, "rivers": 120, "seed": 7}}, {"id": "map", "type": "PolygonMapRaster", "inputs": {"in": "island.out"}, "params": {"perturb_distance": 40, "perturb_feature_size": 400, "river_width": 8, "seed": 7}}, {"id": "shaped", "type": "Power", "inputs": {"in": "map.out"}, "params": {"exponent": 1.5, "pivot": 0, "scale": 900}}, {"id": "detail", "type": "FBM", "inputs": {"roughness": "map.roughness", "amplitude": "map.amplitude"}, "params": {"basis": "perlin", "mode": "multifractal", "feature_size": 600, "amplitude": 80, "octaves": 5, "lacunarity": 2.0, "seed": 8}}, {"id": "coast_fade", "type": "SmoothStep", "inputs": {"in": "map.out"}, "params": {"edge0": 0, "edge1": 150}}, {"id": "dry", "type": "Invert", "inputs": {"in": "map.water"}, "params": {"pivot": 0.5}}, {"id": "detail_mask", "type": "Multiply", "inputs": {"a": "coast_fade.out", "b": "dry.out"}}, {"id": "detail_masked", "type": "Multiply", "inputs": {"a": "detail.out", "b": "detail_mask.out"}}, {"id": "sum", "type": "Add", "inputs": {"a": "shaped.out", "b": "detail_masked.out"}}, {"id": "terrain", "type": "SeaLevelNormalize", "inputs": {"in": "sum.out"}, "params": {"sea_level": 0, "height": 900, "depth": 150}}]}
nodes = island["nodes"]
N = make_adder(nodes)
ISLAND = """scorched, -inf, 0, -inf, 0.16667, #555555
bare, -inf, 0, 0.16667, 0.33333, #888888
tundra, -inf, 0, 0.33333, 0.5, #bbbbaa
snow, -inf, 0, 0.5, inf, #ffffff
temperate_desert, 0, 8, -inf, 0.33333, #c9d29b
shrubland, 0, 8, 0.33333, 0.66667, #889977
taiga, 0, 8, 0.66667, inf, #99aa77
temperate_desert, 8, 16, -inf, 0.16667, #c9d29b
grassland, 8, 16, 0.16667, 0.5, #88aa55
temperate_deciduous_forest, 8, 16, 0.5, 0.83333, #679459
temperate_rain_forest, 8, 16, 0.83333, inf, #448855
subtropical_desert, 16, inf, -inf, 0.16667, #d2b98b
grassland, 16, inf, 0.16667, 0.33333, #88aa55
tropical_seasonal_forest, 16, inf, 0.33333, 0.66667, #559944
tropical_rain_forest, 16, inf, 0.66667, inf, #337755"""
# Climate before erosion: evaporation from the lapse-rate temperature, rain drops from the map's moisture.
N("temperature_initial", "Temperature", {"in": "terrain.out"}, t_december=12, t_june=22, lapse_rate=6.4)
N("evaporation", "Remap", {"in": "temperature_initial.mean"}, in_min=0, in_max=30, out_min=0, out_max=2, clamp=True)
N("eroded", "PipeErosion", {"in": "terrain.out", "moisture": "map.moisture", "temperature": "evaporation.out"},
  duration=1800, rain_mode="drops", drop_chance=0.05, rain_rate=100, capacity=4.0, dissolving=0.1, depositing=0.1,
  evaporation=0.002, sea_level=0, seed=9)
# Biomes of the eroded terrain: temperature by the lapse rate, moisture of the map (Patel's table).
N("temperature", "Temperature", {"in": "eroded.out"}, t_december=12, t_june=22, lapse_rate=6.4)
N("sea", "Threshold", {"in": "eroded.out"}, level=0.5, invert=True)
N("wet", "Max", {"a": "sea.out", "b": "map.water"})
N("biome_temperature", "Add", {"a": "temperature.mean", "b": "wet.out"}, weight_a=1, weight_b=1000)
N("biomes", "Biomes", {"in": "biome_temperature.out", "moisture": "map.moisture"}, table="custom",
  custom_table="water, 500, inf, -inf, inf, #2f5f8a\n" + ISLAND)
# ids of the island table: 0 scorched 1 bare 2 tundra 3 snow 4 temperate_desert 5 shrubland 6 taiga 7 grassland
# 8 temperate_deciduous_forest 9 temperate_rain_forest 10 subtropical_desert 11 tropical_seasonal_forest 12 tropical_rain_forest
# classes: 0 broadleaf tree, 1 conifer, 2 bush, 3 rock
# Plants keep off the shore: a point's biome is the nearest sample's, its height the bilinear one, so next to
# the sea a land sample can put a plant under water. Samples within about 75 m of the sea count as water
# (id 0) for the vegetation only.
N("sea_blur", "Blur", {"in": "sea.out"}, sigma=25)
N("plantable", "Threshold", {"in": "sea_blur.out"}, level=0.001, invert=True)
N("vegetation_biomes", "Multiply", {"a": "biomes.out", "b": "plantable.out"})
N("vegetation", "BiomeScatter", {"in": "vegetation_biomes.out", "height": "eroded.out"},
  table="0 0\n1 0.01 | 3 1\n2 0.02 | 3 1\n3 0.05 | 2 1 | 3 1\n4 0\n5 0.02 | 2 1\n6 0.15 | 2 3 | 0 1\n7 0.35 | 1 1\n8 0.06 | 2 2 | 0 1\n9 0.45 | 0 3 | 1 1 | 2 1\n10 0.6 | 0 2 | 1 2\n11 0.01 | 2 1\n12 0.35 | 0 2 | 2 1\n13 0.6 | 0 1",
  factor=1.0, cell_size=12, scale_range=[0.7, 1.3], seed=5)
add_meshes(N)
N("color", "ColorRamp", {"in": "eroded.out"})
N("mesh_lod", "Resample", {"in": "eroded.out"}, spacing=16, prefilter=True)
N("terrain_mesh", "HeightfieldToMesh", {"in": "mesh_lod.out", "colors": "color.out"}, max_error=1.0)
N("instances", "Instance", {"in": "vegetation.out", "mesh_0": "tree_mesh.out", "mesh_1": "conifer_mesh.out",
   "mesh_2": "bush_mesh.out", "mesh_3": "rock.out"}, names="broadleaf, conifer, bush, rock", missing_mesh="error")
N("save_scene", "WriteScene", {"in": "instances.out", "terrain": "terrain_mesh.out"}, path="voronoi_island/scene.glb")
# Maps.
N("save_polygon_biomes", "WriteImage", {"in": "map.color"}, path="voronoi_island/polygon_biomes.png")
N("save_biomes", "WriteImage", {"in": "biomes.color"}, path="voronoi_island/biomes.png")
N("save_wet", "WriteHeightfield", {"in": "wet.out"}, path="voronoi_island/water_mask.exr")
N("save_biome_id", "WriteHeightfield", {"in": "biomes.out"}, path="voronoi_island/biome_id.exr")
N("save_temperature", "WriteHeightfield", {"in": "temperature.mean"}, path="voronoi_island/temperature.exr")
N("save_moisture", "WriteHeightfield", {"in": "map.moisture"}, path="voronoi_island/moisture.exr")
N("save_polygon_height", "WriteHeightfield", {"in": "map.out"}, path="voronoi_island/polygon_elevation.png")
N("save_initial", "WriteHeightfield", {"in": "terrain.out"}, path="voronoi_island/height_before_erosion.exr")
N("save_height", "WriteHeightfield", {"in": "eroded.out"}, path="voronoi_island/height.exr")
N("save_height_png", "WriteHeightfield", {"in": "eroded.out"}, path="voronoi_island/height.png")
N("save_erosion", "WriteHeightfield", {"in": "eroded.erosion"}, path="voronoi_island/erosion.exr")
N("save_water", "WriteHeightfield", {"in": "eroded.water"}, path="voronoi_island/water.exr")
N("save_rivers", "WriteCurves", {"in": "island.rivers"}, path="voronoi_island/rivers.json")
N("save_tint", "WriteImage", {"in": "color.out"}, path="voronoi_island/height_tint.png")
N("save_points", "WritePoints", {"in": "vegetation.out"}, path="voronoi_island/vegetation.csv")
json.dump(island, open(os.path.join(GRAPHS, "voronoi_island.json"), "w"), indent=2)


# --- Long 2016: rural resources completed (water flow, flood-filled lake, ecosystem vegetation) ---
rural_path = os.path.join(GRAPHS, "rural_resources.json")
g = json.load(open(rural_path))
nodes = g["nodes"]
N = make_adder(nodes)


def node(id):
    return next(n for n in nodes if n["id"] == id)


# Water-flow simulation of one 100 mm storm (Long 2016, section 3.3) and the lake flood-filled from a seed (3.4).
N("water", "WaterFlow", {"in": "terrain.out"}, rainfall=100, infiltration=20, threshold=1e-3, max_iterations=2000)
N("lake", "FloodFill", {"in": "terrain.out"}, seed=[2600, 2550], level_mode="spill")
N("standing", "Max", {"a": "lakes.depth", "b": "water.out"})
N("standing_all", "Max", {"a": "standing.out", "b": "lake.depth"})
node("soil")["inputs"]["water"] = "standing_all.out"
# Outputs the promise tests read (float EXR) and the maps of the gallery.
N("save_height", "WriteHeightfield", {"in": "terrain.out"}, path="rural_resources/height.exr")
N("save_lit_hours", "WriteImage", {"in": "sun.out"}, path="rural_resources/lit_hours.exr")
N("save_temperature_monthly", "WriteImage", {"in": "temperature.out"}, path="rural_resources/temperature.exr")
N("save_cluster_id", "WriteHeightfield", {"in": "clusters.out"}, path="rural_resources/cluster_id.exr")
N("save_water", "WriteHeightfield", {"in": "water.out"}, path="rural_resources/water_depth.exr")
N("save_flux", "WriteHeightfield", {"in": "water.flux"}, path="rural_resources/water_flux.exr")
N("save_flood", "WriteHeightfield", {"in": "lake.out"}, path="rural_resources/flood_surface.exr")
N("save_flood_mask", "WriteHeightfield", {"in": "lake.mask"}, path="rural_resources/flood_mask.png")
N("save_flood_depth", "WriteHeightfield", {"in": "lake.depth"}, path="rural_resources/flood_depth.exr")
N("water_log", "Remap", {"in": "water.flux"}, in_min=0, in_max=3000, out_min=0, out_max=1, clamp=True)
N("water_map", "ColorRamp", {"in": "water_log.out"}, range="fixed", input_min=0, input_max=1,
  gradient=[[0.0, [0.95, 0.95, 0.9, 1]], [0.2, [0.4, 0.7, 0.9, 1]], [1.0, [0.02, 0.1, 0.5, 1]]])
N("save_water_map", "WriteImage", {"in": "water_map.out"}, path="rural_resources/water_flow.png")
# Ecosystem vegetation: each k-means cluster (ecosystem) gets its plant mix; nothing grows in standing water.
N("wet", "Threshold", {"in": "standing_all.out"}, level=0.3)
N("ecosystem_id", "Add", {"a": "clusters.out", "b": "wet.out"}, weight_a=1, weight_b=100)
N("plants", "BiomeScatter", {"in": "ecosystem_id.out", "height": "terrain.out"},
  table="0 0.5 | 0 3 | 2 1\n1 0.3 | 1 2 | 2 1\n2 0.15 | 2 2 | 3 1\n3 0.4 | 1 3 | 0 1\n4 0.2 | 2 1 | 0 1\n5 0.05 | 3 1",
  cell_size=25, scale_range=[0.8, 1.4], seed=6)
add_meshes(N)
N("mesh_lod", "Resample", {"in": "terrain.out"}, spacing=20, prefilter=True)
N("terrain_mesh", "HeightfieldToMesh", {"in": "mesh_lod.out", "colors": "clusters.color"}, max_error=1.0)
N("instances", "Instance", {"in": "plants.out", "mesh_0": "tree_mesh.out", "mesh_1": "conifer_mesh.out",
   "mesh_2": "bush_mesh.out", "mesh_3": "rock.out"}, names="broadleaf, conifer, bush, rock", missing_mesh="error")
N("save_scene", "WriteScene", {"in": "instances.out", "terrain": "terrain_mesh.out"}, path="rural_resources/scene.glb")
json.dump(g, open(rural_path, "w"), indent=2)


# --- Potter 2017: the forest ---
g = {"format": "orogen-graph", "version": 4, "domain": {"size": [1024, 1024], "resolution": [257, 257]}, "nodes": []}
nodes = g["nodes"]
N = make_adder(nodes)
# Layered Perlin height (Potter 2017: Perlin textures of halving size and weight, summed).
N("noise", "FBM", None, basis="perlin", mode="fbm", feature_size=600, amplitude=170, octaves=6, gain=0.5, seed=4)
N("terrain", "Remap", {"in": "noise.out"}, in_min=-200, in_max=200, out_min=40, out_max=440, clamp=False)
# Splat rules: grass on gentle low ground, rock on steep slopes, dirt between.
N("splat", "SplatWeights", {"in": "terrain.out"},
  layers="grass: slope < 22 ~ 5, height < 400 ~ 30\ndirt: weight = 0.2, slope < 34 ~ 5\nrock: slope > 28 ~ 5\n")
N("grass", "ImageChannel", {"in": "splat.out"}, name="grass")
N("rock_layer", "ImageChannel", {"in": "splat.out"}, name="rock")
N("hillshade", "Hillshade", {"in": "terrain.out"}, azimuth=315, altitude=50)
N("color", "ColorByLayers", {"in": "splat.out", "shade": "hillshade.out"},
  colors="grass #5b7f32\ndirt #7a6248\nrock #80786f", shade_strength=0.5)
# Trees: Bridson Poisson disk on grass (mask), two classes with their own radii, then 50 years of life cycle.
N("tree_seedlings", "PoissonDisk", {"mask": "grass.out", "height": "terrain.out"},
  class_count=2, radius_0=9, radius_1=7, first_class=0, seed=3)
N("forest", "ForestLifeCycle", {"in": "tree_seedlings.out", "suitability": "grass.out", "height": "terrain.out"},
  years=50, max_age=90, maturity_age=25, min_scale=0.25, max_scale=1.0, seed_distance=15, seed_probability=0.08,
  competition=9, seed=8)
# Rocks on the rock layer (a separate pass: rocks may sit near trees).
N("rocks", "PoissonDisk", {"mask": "rock_layer.out", "height": "terrain.out"}, class_count=1, radius_0=14, first_class=2, seed=21)
# Undergrowth: shade-loving ferns under the crowns and sun-loving flowers in the open, for the sun at a chosen
# hour and day (Canberra's latitude, a summer afternoon).
N("fern_candidates", "PoissonDisk", {"mask": "grass.out", "height": "terrain.out"}, class_count=1, radius_0=3.5, first_class=3, seed=22)
N("undergrowth", "ShadePlacement", {"in": "fern_candidates.out", "casters": "forest.out", "height": "terrain.out"},
  preference="shade", sun="time", latitude=-35.3, day_of_year=15, hour=16.5, crown_radius=4, crown_height=9)
N("flower_candidates", "PoissonDisk", {"mask": "grass.out", "height": "terrain.out"}, class_count=1, radius_0=5, first_class=4, seed=23)
N("flowers", "ShadePlacement", {"in": "flower_candidates.out", "casters": "forest.out", "height": "terrain.out"},
  preference="sun", sun="time", latitude=-35.3, day_of_year=15, hour=16.5, crown_radius=4, crown_height=9)
N("placed", "MergePoints", {"a": "forest.out", "b": "rocks.out", "c": "undergrowth.out", "d": "flowers.out"})
# Instance meshes.
add_meshes(N)
N("fern", "LSystem", None, axiom="X", rules="// ABOP Fig. 1.24d\nX -> F[+X]F[-X]+X\nF -> FF", iterations=5)
N("fern_turtle", "Turtle3D", {"in": "fern.out"}, angle=20, step=0.05, width=0.03, color=[0.12, 0.3, 0.05, 1.0])
N("fern_mesh", "TreeMesh", {"in": "fern_turtle.out", "leaves": "fern_turtle.leaves"}, sides=3, max_triangles=1000)
N("mesh_lod", "Resample", {"in": "terrain.out"}, spacing=8, prefilter=False)
N("mesh", "HeightfieldToMesh", {"in": "mesh_lod.out", "colors": "color.out"}, max_error=0.5)
N("instances", "Instance", {"in": "placed.out", "mesh_0": "tree_mesh.out", "mesh_1": "conifer_mesh.out",
   "mesh_2": "rock.out", "mesh_3": "fern_mesh.out", "mesh_4": "bush_mesh.out"},
  names="broadleaf, conifer, rock, fern, flower", missing_mesh="error")
N("save_scene", "WriteScene", {"in": "instances.out", "terrain": "mesh.out"}, path="forest/scene.glb")
N("save_points", "WritePoints", {"in": "placed.out"}, path="forest/points.csv")
N("save_color", "WriteImage", {"in": "color.out"}, path="forest/color.png")
N("save_splat", "WriteImage", {"in": "splat.out"}, path="forest/splat.png")
N("save_dominant", "WriteHeightfield", {"in": "splat.dominant"}, path="forest/dominant.png", range="fixed", height_min=0, height_max=2)
N("save_height", "WriteHeightfield", {"in": "terrain.out"}, path="forest/height.exr")
N("save_shade", "WriteHeightfield", {"in": "undergrowth.shade"}, path="forest/shade.png", range="fixed", height_min=0, height_max=1)
json.dump(g, open(os.path.join(GRAPHS, "forest.json"), "w"), indent=2)
