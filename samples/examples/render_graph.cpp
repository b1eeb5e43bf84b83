// example-render-graph: builds a small scene graph in code (camera, light, materials, meshes
// under transforms, one mesh shared by two paths) and renders it to a PNG.
//
//   example-render-graph [OUT.png]
//
// Exits 1 when the picture did not come out as built: too few pixels hit, no shadow rays, or
// the shared crate not drawn on both of its paths.
#include <tracegraph/tracegraph.h>

#include <iostream>
#include <set>
#include <string>

using namespace tg;

namespace {

/// An axis-aligned box from lo to hi, 12 triangles facing outwards.
ref_ptr<nodes::Mesh> box(const Vec3f& lo, const Vec3f& hi) {
  std::vector<Vec3f> p;
  for (int i = 0; i < 8; ++i)
    p.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  return nodes::Mesh::create(std::move(p), {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                            2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5});
}

ref_ptr<nodes::Material> material(Color diffuse, Color specular = {}) {
  ref_ptr<nodes::Material> m = nodes::Material::create();
  m->diffuseColor = diffuse;
  m->specularColor = specular;
  m->shininess = 40.0f;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string output = argc > 1 ? argv[1] : "example-render-graph.png";

  // The graph: Inventor-style traversal state, so a Transform or Material applies to the
  // shapes after it inside the same Separator.
  ref_ptr<nodes::Separator> root = nodes::Separator::create();

  ref_ptr<nodes::Camera> camera = nodes::Camera::create();
  camera->lookAt({2.0f, 2.0f, 4.0f}, {0.0f, 0.4f, 0.0f}, {0.0f, 1.0f, 0.0f});
  camera->fov = 0.8f;
  root->addChild(camera);

  ref_ptr<nodes::PointLight> light = nodes::PointLight::create();
  light->location = Vec3f{-2.0f, 5.0f, 3.0f};
  root->addChild(light);

  // A floor.
  ref_ptr<nodes::Separator> floor = nodes::Separator::create();
  floor->addChild(material({0.7f, 0.7f, 0.65f}));
  floor->addChild(box({-5.0f, -0.1f, -5.0f}, {5.0f, 0.0f, 5.0f}));
  root->addChild(floor);

  // One crate on two paths (what X3D's DEF/USE writes): the graph holds its triangles once,
  // and hits on either copy map back to the same Mesh node.
  ref_ptr<nodes::Separator> crate = nodes::Separator::create();
  crate->addChild(material({0.8f, 0.35f, 0.1f}, {0.3f, 0.3f, 0.3f}));
  crate->addChild(box({-0.5f, 0.0f, -0.5f}, {0.5f, 1.0f, 0.5f}));
  for (float x : {-1.2f, 1.2f}) {
    ref_ptr<nodes::Separator> placed = nodes::Separator::create();
    ref_ptr<nodes::Transform> where = nodes::Transform::create();
    where->translation = Vec3f{x, 0.0f, 0.0f};
    where->rotation = Rotation{{0.0f, 1.0f, 0.0f}, 0.4f * x};
    placed->addChild(where);
    placed->addChild(crate);
    root->addChild(placed);
  }

  // Sync the graph into the backend scene, then render what it holds.
  SceneGraph graph;
  graph.setRoot(root);
  graph.advanceTo(0.0);
  FrameStats stats = graph.sync();

  RenderSettings settings;
  settings.mode = RenderMode::Whitted;
  SceneRenderer renderer(graph, settings);
  renderer.setLook({{0.3f, 0.4f, 0.6f}, {0.2f, 0.2f, 0.2f}});
  renderer.update();
  Frame frame;
  renderer.render(renderer.camera(160, 120), frame, &stats);
  try {
    writePng(frame.beauty, output);
  } catch (const Error& e) {
    std::cerr << "example-render-graph: " << e.what() << "\n";
    return 1;
  }
  std::cout << toJson(stats) << "\n";

  // What the picture must show, read back from the AOVs.
  std::size_t hitPixels = 0;
  std::set<const ShapeNode*> shapes;
  std::size_t crateLeft = 0, crateRight = 0;  // pixels of the shared crate mesh per image half
  const IdImage& ids = frame.instanceId;
  for (std::uint32_t y = 0; y < ids.height(); ++y)
    for (std::uint32_t x = 0; x < ids.width(); ++x) {
      Hit hit;
      hit.instanceId = ids.at(x, y);
      hit.primId = frame.primId.at(x, y);
      if (!hit.valid()) continue;
      ++hitPixels;
      const HitInfo info = graph.hitInfo(hit);
      shapes.insert(info.shape);
      if (info.shape == crate->child(1)) ++(x < ids.width() / 2 ? crateLeft : crateRight);
    }
  const std::size_t pixels = std::size_t{ids.width()} * ids.height();
  std::cout << "wrote " << output << ": " << hitPixels << " of " << pixels << " pixels hit, "
            << shapes.size() << " meshes seen, the shared crate in " << crateLeft << " + "
            << crateRight << " pixels (left + right), " << stats.rays.shadow << " shadow rays\n";

  int failures = 0;
  auto expect = [&](bool ok, const char* what) {
    if (!ok) {
      std::cerr << "example-render-graph: FAILED: " << what << "\n";
      ++failures;
    }
  };
  expect(hitPixels > pixels / 2, "the floor and crates cover most of the image");
  expect(shapes.size() == 2, "both meshes (floor and crate) are visible");
  expect(crateLeft > 0 && crateRight > 0, "the shared crate is drawn on both of its paths");
  expect(stats.rays.shadow > 0, "Whitted mode traces shadow rays towards the light");
  return failures == 0 ? 0 : 1;
}
