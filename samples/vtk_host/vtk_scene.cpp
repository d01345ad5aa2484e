#include "vtk_scene.h"

#include <algorithm>
#include <cmath>

#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCellArray.h>
#include <vtkConeSource.h>
#include <vtkContourFilter.h>
#include <vtkCoordinate.h>
#include <vtkCylinderSource.h>
#include <vtkElevationFilter.h>
#include <vtkGlyph3D.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkQuadric.h>
#include <vtkRenderer.h>
#include <vtkSampleFunction.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkUnsignedCharArray.h>

#include "atmo_support/image.h"

namespace atmo::vtk_host {

namespace hs = atmo::host_scene;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kAmbientDisplay = 0.25;  // ambient coefficient without the plugin's sky light

// The heightfield as triangles, coloured by height (meadow to rock), curvature dropped.
vtkSmartPointer<vtkActor> terrain_actor(const hs::Terrain& terrain) {
  const int n = terrain.grid();
  const double size = terrain.options().size_m, relief = terrain.options().relief_m;
  const std::vector<float>& h = terrain.heights();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetNumberOfComponents(3);
  colors->SetName("albedo");
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double e = -0.5 * size + size * i / (n - 1), north = -0.5 * size + size * j / (n - 1);
      const double z = h[size_t(j) * n + i];
      points->InsertNextPoint(e, north, z - hs::curvature_drop_m(e, north));
      const double t = std::clamp(z / std::max(relief, 1.0), 0.0, 1.0);
      const unsigned char rgb[3] = {static_cast<unsigned char>(70 + 70 * t), static_cast<unsigned char>(105 + 15 * t),
                                    static_cast<unsigned char>(50 + 45 * t)};
      colors->InsertNextTypedTuple(rgb);
    }
  }
  vtkNew<vtkCellArray> triangles;
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const vtkIdType a = vtkIdType(j) * n + i, b = a + 1, c = a + n, d = c + 1;
      const vtkIdType t0[3] = {a, b, d}, t1[3] = {a, d, c};
      triangles->InsertNextCell(3, t0);
      triangles->InsertNextCell(3, t1);
    }
  }
  vtkNew<vtkPolyData> mesh;
  mesh->SetPoints(points);
  mesh->SetPolys(triangles);
  mesh->GetPointData()->SetScalars(colors);
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(mesh);
  normals->SplittingOff();
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(normals->GetOutputPort());
  mapper->SetColorModeToDirectScalars();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  return actor;
}

// A dataset-like object: an isosurface of a quadric (a one-sheet hyperboloid
// cut by its box), coloured by height, 1.2 km across, hovering at `centre`.
vtkSmartPointer<vtkActor> isosurface_actor(const double centre[3]) {
  vtkNew<vtkQuadric> quadric;
  quadric->SetCoefficients(1.0, 1.0, -0.6, 0, 0, 0, 0, 0, 0, -0.15);
  vtkNew<vtkSampleFunction> sample;
  sample->SetImplicitFunction(quadric);
  sample->SetModelBounds(-1, 1, -1, 1, -1, 1);
  sample->SetSampleDimensions(40, 40, 40);
  vtkNew<vtkContourFilter> contour;
  contour->SetInputConnection(sample->GetOutputPort());
  contour->SetValue(0, 0.0);
  vtkNew<vtkTransform> place;
  place->Translate(centre);
  place->Scale(600.0, 600.0, 600.0);
  vtkNew<vtkTransformPolyDataFilter> placed;
  placed->SetInputConnection(contour->GetOutputPort());
  placed->SetTransform(place);
  vtkNew<vtkElevationFilter> elevation;
  elevation->SetInputConnection(placed->GetOutputPort());
  elevation->SetLowPoint(0, 0, centre[2] - 600.0);
  elevation->SetHighPoint(0, 0, centre[2] + 600.0);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(elevation->GetOutputPort());
  mapper->SetScalarRange(0.0, 1.0);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  return actor;
}

// Masts 400 m tall standing on the terrain along the view, `distances` metres north of `from`.
vtkSmartPointer<vtkActor> masts_actor(const hs::Terrain& terrain, const double from[2],
                                      const std::vector<double>& distances) {
  vtkNew<vtkPoints> points;
  for (size_t k = 0; k < distances.size(); ++k) {
    const double e = from[0] + (k % 2 ? 1.0 : -1.0) * (300.0 + 0.08 * distances[k]);
    const double north = from[1] + distances[k];
    points->InsertNextPoint(e, north, terrain.height_at(e, north) - hs::curvature_drop_m(e, north) + 200.0);
  }
  vtkNew<vtkPolyData> where;
  where->SetPoints(points);
  vtkNew<vtkCylinderSource> mast;  // along y: turned upright below
  mast->SetRadius(40.0);
  mast->SetHeight(400.0);
  mast->SetResolution(16);
  vtkNew<vtkTransform> upright;
  upright->RotateX(90.0);
  vtkNew<vtkTransformPolyDataFilter> upright_mast;
  upright_mast->SetInputConnection(mast->GetOutputPort());
  upright_mast->SetTransform(upright);
  vtkNew<vtkGlyph3D> glyphs;
  glyphs->SetInputData(where);
  glyphs->SetSourceConnection(upright_mast->GetOutputPort());
  glyphs->SetScaleModeToDataScalingOff();
  glyphs->OrientOff();
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(glyphs->GetOutputPort());
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.95, 0.35, 0.1);
  return actor;
}

}  // namespace

Scene build_scene(const hs::Terrain& terrain) {
  Scene scene;
  const double half = 0.5 * terrain.options().size_m;
  const double start[2] = {0.0, -half + 1000.0};
  const double ground = terrain.height_at(start[0], start[1]) - hs::curvature_drop_m(start[0], start[1]);
  scene.camera_position = {start[0], start[1], ground + 400.0};
  scene.camera_focal_point = {start[0], start[1] + 10000.0, ground + 400.0 - 10000.0 * std::tan(4.0 * kPi / 180.0)};
  const double iso[3] = {1500.0, start[1] + 7000.0,
                         terrain.height_at(1500.0, start[1] + 7000.0) -
                             hs::curvature_drop_m(1500.0, start[1] + 7000.0) + 900.0};
  scene.actors.push_back(terrain_actor(terrain));
  scene.actors.push_back(isosurface_actor(iso));
  scene.actors.push_back(masts_actor(terrain, start, {1500.0, 3000.0, 6000.0, 12000.0, 20000.0, 30000.0}));
  scene.sun = vtkSmartPointer<vtkLight>::New();
  scene.sun->SetLightTypeToSceneLight();
  scene.sun->PositionalOff();
  scene.sun->SetFocalPoint(0.0, 0.0, 0.0);
  apply_default_lighting(scene);
  return scene;
}

void apply_lighting(Scene& scene, const AtmoLighting& l, bool linear, double exposure_scale) {
  const double* e = l.sun_illuminance_lux;
  const double peak = std::max({e[0], e[1], e[2]});
  scene.sun->SetPosition(l.sun_direction_enu);  // a scene light shines from its position to its focal point
  // Kept on below the horizon with no intensity: VTK draws unlit (full colour) when no light is on.
  scene.sun->SetSwitch(true);
  if (peak > 0.0) scene.sun->SetDiffuseColor(e[0] / peak, e[1] / peak, e[2] / peak);
  const double exposure = exposure_scale > 0.0 ? exposure_scale : 1.0 / (1.2 * 32768.0);
  const double sun = l.sun_elevation_rad > 0.0 ? peak * exposure / kPi : 0.0;  // a white Lambertian surface
  // VTK's OpenGL2 ambient term is the actor's colour x its ambient coefficient (lights add none):
  // the sky's illuminance on a horizontal surface.
  const double* sky = l.sky_illuminance_horizontal_lux;
  const double ambient = (0.2126 * sky[0] + 0.7152 * sky[1] + 0.0722 * sky[2]) * exposure / kPi;
  // Linear: the plugin's output units. Display: VTK's colours are display-referred, so the light
  // is what the plugin's DISPLAY_SRGB encoding makes of a white surface under it.
  const auto display = [](double x) {
    return double(support::srgb_encode(support::aces_filmic(static_cast<float>(x))));
  };
  scene.sun->SetIntensity(linear ? sun : display(sun));
  for (auto& actor : scene.actors) {
    actor->GetProperty()->SetAmbient(linear ? ambient : display(ambient));
    actor->GetProperty()->SetDiffuse(1.0);
  }
}

void apply_default_lighting(Scene& scene) {
  scene.sun->SetPosition(-0.35, -0.6, 0.72);
  scene.sun->SetSwitch(true);
  scene.sun->SetIntensity(1.0);
  for (auto& actor : scene.actors) actor->GetProperty()->SetAmbient(kAmbientDisplay);
}

vtkSmartPointer<vtkRenderer> build_overlay(const std::array<double, 4>& f) {
  auto overlay = vtkSmartPointer<vtkRenderer>::New();
  overlay->SetLayer(1);
  overlay->SetViewport(f[0], f[1], f[2], f[3]);
  overlay->SetPreserveColorBuffer(0);  // SetLayer(1) turned it on: this box is VTK's own pixels only
  overlay->SetBackground(0.12, 0.12, 0.16);
  overlay->SetBackgroundAlpha(1.0);
  overlay->InteractiveOff();

  vtkNew<vtkConeSource> cone;
  cone->SetResolution(24);
  vtkNew<vtkElevationFilter> colour;
  colour->SetInputConnection(cone->GetOutputPort());
  colour->SetLowPoint(-0.5, 0, 0);
  colour->SetHighPoint(0.5, 0, 0);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(colour->GetOutputPort());
  vtkNew<vtkActor> glyph;
  glyph->SetMapper(mapper);
  glyph->RotateY(-30.0);
  glyph->RotateX(20.0);
  overlay->AddActor(glyph);

  // A 2D quad with a colour per corner (interpolated), over the lower left of the box.
  vtkNew<vtkPoints> corners;
  corners->InsertNextPoint(0.05, 0.05, 0.0);
  corners->InsertNextPoint(0.45, 0.05, 0.0);
  corners->InsertNextPoint(0.45, 0.30, 0.0);
  corners->InsertNextPoint(0.05, 0.30, 0.0);
  vtkNew<vtkCellArray> quad;
  const vtkIdType ids[4] = {0, 1, 2, 3};
  quad->InsertNextCell(4, ids);
  vtkNew<vtkUnsignedCharArray> rgb;
  rgb->SetNumberOfComponents(3);
  const unsigned char c[4][3] = {{230, 40, 40}, {40, 200, 60}, {40, 80, 230}, {240, 220, 40}};
  for (const auto& v : c) rgb->InsertNextTypedTuple(v);
  vtkNew<vtkPolyData> quad_data;
  quad_data->SetPoints(corners);
  quad_data->SetPolys(quad);
  quad_data->GetPointData()->SetScalars(rgb);
  vtkNew<vtkCoordinate> normalized;
  normalized->SetCoordinateSystemToNormalizedViewport();
  vtkNew<vtkPolyDataMapper2D> mapper2d;
  mapper2d->SetInputData(quad_data);
  mapper2d->SetTransformCoordinate(normalized);
  mapper2d->SetColorModeToDirectScalars();
  vtkNew<vtkActor2D> quad_actor;
  quad_actor->SetMapper(mapper2d);
  overlay->AddActor2D(quad_actor);

  vtkNew<vtkTextActor> caption;
  caption->SetInput("VTK overlay");
  caption->GetTextProperty()->SetFontSize(12);
  caption->GetTextProperty()->SetColor(1.0, 1.0, 1.0);
  caption->SetPosition(4.0, 4.0);  // viewport pixels of the overlay
  overlay->AddActor2D(caption);
  overlay->ResetCamera();
  return overlay;
}

}  // namespace atmo::vtk_host
