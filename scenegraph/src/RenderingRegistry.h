/// @file RenderingRegistry.h
/// Process-wide record of the roots whose graphs are being rendered (internal).
#pragma once

namespace tg {
class Node;
}

namespace tg::detail {

/// Marks `root`'s graph as being rendered (counted: may nest).
void beginRendering(const Node* root);
/// Undoes one beginRendering(root).
void endRendering(const Node* root);
/// True when `node` is, or lies below, a root being rendered. Costs one atomic load when
/// nothing renders, which is the case for every edit made between frames.
bool isUnderRenderingRoot(const Node& node);

}  // namespace tg::detail
