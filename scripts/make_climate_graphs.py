"""Writes graphs/rural_resources.json and graphs/textured_terrain.json (run from anywhere). The seed graph of
rural_resources.json is completed by scripts/make_seed_graphs.py, which runs this script first."""
import json
import os

GRAPHS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "graphs")
def node(id, type, params=None, inputs=None):
    n = {"id": id, "type": type}
    if inputs: n["inputs"] = inputs
    if params: n["params"] = params
    return n
def gradient(stops):
    return [[p, list(c)] for p, c in stops]

heat = gradient([(0.0,(0.02,0.05,0.35,1)),(0.35,(0.1,0.55,0.75,1)),(0.6,(0.85,0.85,0.35,1)),(1.0,(0.8,0.1,0.05,1))])
gray = gradient([(0.0,(0,0,0,1)),(1.0,(1,1,1,1))])
blues = gradient([(0.0,(0.25,0.18,0.08,1)),(0.5,(0.35,0.6,0.3,1)),(1.0,(0.05,0.2,0.7,1))])

rain = [[m, v] for m, v in zip(range(1,13), [120,100,90,80,70,60,50,60,80,100,120,130])]
rural = {"format": "orogen-graph", "version": 4,
  "domain": {"size": [5100, 5100], "resolution": [256, 256]},
  "nodes": [
    node("noise", "FBM", {"basis": "perlin", "mode": "fbm", "feature_size": 1800, "amplitude": 420, "octaves": 7, "seed": 12}),
    node("base", "Constant", {"value": 380}),
    node("terrain", "Add", None, {"a": "noise.out", "b": "base.out"}),
    node("lakes", "Lakes", {"min_depth": 0.5, "min_area": 20000}, {"in": "terrain.out"}),
    node("flow", "FlowAccumulation", {"method": "mfd", "fill": True}, {"in": "terrain.out"}),
    node("sun", "SunIllumination", {"latitude": 45, "month": 12, "hour": 10, "time_step": 1}, {"in": "terrain.out"}),
    node("temperature", "Temperature", {"t_december": 2, "t_june": 21, "lapse_rate": 6.4, "illumination_gain": 0.3,
                                        "reference_hours": 12}, {"in": "terrain.out", "illumination": "sun.out"}),
    node("soil", "SoilHumidity", {"rainfall": rain, "infiltration": 6, "max_slope": 30},
         {"in": "terrain.out", "wetness": "flow.flow", "water": "lakes.depth"}),
    node("stack", "ResourceStack", None, {"in": "terrain.out", "temperature": "temperature.out",
                                          "illumination": "sun.out", "humidity": "soil.out"}),
    node("clusters", "KMeansClusters", {"k": 6, "max_iterations": 100}, {"in": "stack.out"}),
    node("moisture", "Remap", {"in_min": 300, "in_max": 1060, "out_min": 0, "out_max": 1, "clamp": True}, {"in": "soil.annual"}),
    node("biomes", "Biomes", {"table": "island"}, {"in": "temperature.mean", "moisture": "moisture.out"}),
    node("sun_june", "ImageChannel", {"name": "jun"}, {"in": "sun.out"}),
    node("sun_dec", "ImageChannel", {"name": "dec"}, {"in": "sun.out"}),
    node("june_map", "ColorRamp", {"range": "fixed", "input_min": 0, "input_max": 16, "gradient": gray}, {"in": "sun_june.out"}),
    node("dec_map", "ColorRamp", {"range": "fixed", "input_min": 0, "input_max": 9, "gradient": gray}, {"in": "sun_dec.out"}),
    node("shadow_map", "ColorRamp", {"range": "fixed", "input_min": 0, "input_max": 1, "gradient": gray}, {"in": "sun.lit"}),
    node("temp_map", "ColorRamp", {"range": "fixed", "input_min": 5, "input_max": 13, "gradient": heat}, {"in": "temperature.mean"}),
    node("soil_map", "ColorRamp", {"range": "fixed", "input_min": 400, "input_max": 1060, "gradient": blues}, {"in": "soil.annual"}),
    node("save_sun_june", "WriteImage", {"path": "rural_resources/lit_hours_june.png"}, {"in": "june_map.out"}),
    node("save_sun_dec", "WriteImage", {"path": "rural_resources/lit_hours_december.png"}, {"in": "dec_map.out"}),
    node("save_shadow", "WriteImage", {"path": "rural_resources/shadows_december_10h.png"}, {"in": "shadow_map.out"}),
    node("save_irradiance", "WriteImage", {"path": "rural_resources/irradiance.exr"}, {"in": "sun.irradiance"}),
    node("save_temperature", "WriteImage", {"path": "rural_resources/temperature_mean.png"}, {"in": "temp_map.out"}),
    node("save_soil", "WriteImage", {"path": "rural_resources/soil_humidity_annual.png"}, {"in": "soil_map.out"}),
    node("save_stack", "WriteImage", {"path": "rural_resources/resources.exr"}, {"in": "stack.out"}),
    node("save_clusters", "WriteImage", {"path": "rural_resources/ecosystems.png"}, {"in": "clusters.color"}),
    node("save_biomes", "WriteImage", {"path": "rural_resources/biomes.png"}, {"in": "biomes.color"}),
    node("save_lakes", "WriteHeightfield", {"path": "rural_resources/lake_depth.exr"}, {"in": "lakes.depth"}),
  ]}
json.dump(rural, open(os.path.join(GRAPHS, "rural_resources.json"), "w"), indent=2)

layers = ("grass: slope < 28 ~ 6, height > 6 ~ 3, height < 850 ~ 100\n"
          "dirt: weight = 0.2, slope < 40 ~ 8\n"
          "rock: slope > 34 ~ 6\n"
          "snow: height > 900 ~ 80, slope < 48 ~ 6\n"
          "sand: height < 5 ~ 3, slope < 15 ~ 5\n"
          "wet: weight = 2, flow > 0.55 ~ 0.08, slope < 25 ~ 5\n")
colors = "grass #5b7f32, dirt #7a6248, rock #80786f, snow #f4f6f8, sand #d9c48f, wet #3f5a3a"
textured = {"format": "orogen-graph", "version": 4,
  "domain": {"size": [6000, 6000], "resolution": [384, 384]},
  "nodes": [
    node("relief", "FBM", {"basis": "simplex", "mode": "fbm", "feature_size": 7000, "amplitude": 900, "octaves": 7, "gain": 0.42, "seed": 4}),
    node("base", "Constant", {"value": 450}),
    node("terrain", "Add", None, {"a": "relief.out", "b": "base.out"}),
    node("flow", "FlowAccumulation", {"method": "mfd", "fill": True}, {"in": "terrain.out"}),
    node("splat", "SplatWeights", {"layers": layers}, {"in": "terrain.out", "flow": "flow.flow"}),
    node("ao", "AmbientOcclusion", {"radius": 250, "directions": 16}, {"in": "terrain.out"}),
    node("cavity", "Cavity", {"radius": 40, "directions": 8}, {"in": "terrain.out"}),
    node("hillshade", "Hillshade", {"azimuth": 315, "altitude": 40}, {"in": "terrain.out"}),
    node("shade", "Multiply", None, {"a": "ao.out", "b": "hillshade.out"}),
    node("color", "ColorByLayers", {"colors": colors, "shade_strength": 0.8}, {"in": "splat.out", "shade": "shade.out"}),
    node("mesh", "HeightfieldToMesh", {"max_error": 2.0}, {"in": "terrain.out"}),
    node("save_color", "WriteImage", {"path": "textured_terrain/color.png"}, {"in": "color.out"}),
    node("save_splat0", "WriteImage", {"path": "textured_terrain/splat0.png", "srgb": False}, {"in": "splat.splat0"}),
    node("save_splat1", "WriteImage", {"path": "textured_terrain/splat1.png", "srgb": False}, {"in": "splat.splat1"}),
    node("save_weights", "WriteImage", {"path": "textured_terrain/weights.exr"}, {"in": "splat.out"}),
    node("save_hillshade", "WriteImage", {"path": "textured_terrain/hillshade.png"}, {"in": "hillshade.image"}),
    node("save_ao", "WriteHeightfield", {"path": "textured_terrain/ao.png", "range": "fixed", "height_min": 0, "height_max": 1}, {"in": "ao.out"}),
    node("save_cavity", "WriteHeightfield", {"path": "textured_terrain/cavity.png", "range": "fixed", "height_min": 0, "height_max": 1}, {"in": "cavity.out"}),
    node("save_height", "WriteHeightfield", {"path": "textured_terrain/height.exr"}, {"in": "terrain.out"}),
    node("save_mesh", "WriteMesh", {"path": "textured_terrain/terrain.obj", "texture": "color.png"}, {"in": "mesh.out"}),
  ]}
json.dump(textured, open(os.path.join(GRAPHS, "textured_terrain.json"), "w"), indent=2)
