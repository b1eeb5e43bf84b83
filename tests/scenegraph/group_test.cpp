// Groups: children, parent back-links, reference-counted ownership, cycle rejection.
#define BOOST_TEST_MODULE group
#include <boost/test/unit_test.hpp>

#include "GraphTestUtil.h"
#include "tracegraph/backend/Error.h"

using namespace tg;
using namespace tg::nodes;
using namespace tgtest;

namespace {

/// A node that reports its destruction.
class Probe : public Node {
 public:
  static ref_ptr<Probe> create(bool& destroyed) { return ref_ptr<Probe>(new Probe(destroyed)); }

 protected:
  explicit Probe(bool& destroyed) : destroyed_(destroyed) {}
  ~Probe() override { destroyed_ = true; }

 private:
  bool& destroyed_;
};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

BOOST_AUTO_TEST_CASE(children_and_parent_links) {
  auto g = Group::create();
  auto a = Transform::create(), b = Transform::create(), c = Transform::create();
  g->addChild(a);
  g->addChild(c);
  g->insertChild(1, b);
  BOOST_TEST(g->numChildren() == 3u);
  BOOST_TEST(g->child(1) == b.get());
  BOOST_TEST(g->findChild(c.get()) == 2);
  BOOST_TEST(b->parents().size() == 1u);
  BOOST_TEST(b->parents()[0] == g.get());
  g->addChild(b);  // the same child twice: two links
  BOOST_TEST(b->parents().size() == 2u);
  BOOST_TEST(g->removeChild(b.get()));
  BOOST_TEST(b->parents().size() == 1u);
  g->replaceChild(0, c);
  BOOST_TEST(a->parents().empty());
  BOOST_TEST(c->parents().size() == 2u);
  g->removeAllChildren();
  BOOST_TEST(c->parents().empty());
  BOOST_CHECK_THROW(g->removeChild(std::size_t(0)), Error);
  BOOST_CHECK_THROW(g->insertChild(5, a), Error);
  BOOST_CHECK_THROW(g->addChild(nullptr), Error);
}

BOOST_AUTO_TEST_CASE(children_are_owned_by_reference) {
  bool destroyed = false;
  auto g = Group::create();
  {
    auto p = Probe::create(destroyed);
    g->addChild(p);
    auto other = Group::create();
    other->addChild(p);  // two owners
    BOOST_TEST(p->referenceCount() == 3);
  }
  BOOST_TEST(!destroyed);
  g->removeChild(std::size_t(0));
  BOOST_TEST(destroyed);

  // A group going away releases its children and their back-links.
  auto kept = Transform::create();
  {
    auto temp = Group::create();
    temp->addChild(kept);
    BOOST_TEST(kept->parents().size() == 1u);
  }
  BOOST_TEST(kept->parents().empty());
}

BOOST_AUTO_TEST_CASE(cycles_are_rejected_and_the_graph_is_unchanged) {
  auto root = Separator::create();
  auto mid = Group::create();
  auto leaf = Separator::create();
  root->addChild(mid);
  mid->addChild(leaf);
  try {
    leaf->addChild(root);
    BOOST_FAIL("expected tg::Error");
  } catch (const Error& e) {
    BOOST_TEST(contains(e.what(), "Group::addChild"));
    BOOST_TEST(contains(e.what(), "cycle"));
  }
  try {
    leaf->insertChild(0, leaf);
    BOOST_FAIL("expected tg::Error");
  } catch (const Error& e) {
    BOOST_TEST(contains(e.what(), "Group::insertChild"));
  }
  BOOST_CHECK_THROW(mid->replaceChild(0, root), Error);
  BOOST_TEST(leaf->numChildren() == 0u);
  BOOST_TEST(mid->child(0) == leaf.get());
  BOOST_TEST(root->parents().empty());
  BOOST_TEST(leaf->parents().size() == 1u);
  // Sharing is not a cycle.
  root->addChild(leaf);
  BOOST_TEST(leaf->parents().size() == 2u);
}

BOOST_AUTO_TEST_CASE(names_appear_in_labels) {
  auto t = Transform::create();
  BOOST_TEST(t->label() == "Transform");
  t->setName("arm");
  BOOST_TEST(t->label() == "Transform 'arm'");
}
