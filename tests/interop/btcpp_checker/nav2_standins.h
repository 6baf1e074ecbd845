// Stand-ins for Nav2's ROS-free control nodes, which BehaviorTree.CPP does not have.
//
// Written for this checker from the behaviour Nav2 Jazzy documents for each node
// (docs.nav2.org, "Behavior Tree XML Nodes"), on BT.CPP 4's ControlNode/DecoratorNode:
// no Nav2 code is copied. They let the checker tick the exported Nav2 navigator trees.
//  - RecoveryNode: tick the action (child 0); when it fails, tick the recovery (child 1)
//    and, when that succeeds, the action again, up to number_of_retries recoveries; a
//    skipped action skips the node, a skipped recovery fails it without counting a retry.
//  - PipelineSequence: every tick, tick the children in order; a RUNNING child before
//    the furthest one reached so far does not stop the walk; FAILURE halts all.
//  - RoundRobin: tick one child at a time, moving to the next when it completes; the
//    first success succeeds (and the next run starts after it), all failing fails.
//  - RateController: tick the child on the node's first tick, while it runs, and once
//    1/hz seconds have passed since its last success (else RUNNING).
//  - SingleTrigger: tick the child until it completes once; afterwards FAILURE until
//    the node is reset (halted, or its parent finished).
#pragma once

#include <behaviortree_cpp/control_node.h>
#include <behaviortree_cpp/decorator_node.h>

#include <chrono>
#include <memory>
#include <string>

namespace nav2_standins
{
using BT::NodeStatus;

class RecoveryNode : public BT::ControlNode
{
public:
  RecoveryNode(const std::string& name, const BT::NodeConfig& config)
    : BT::ControlNode(name, config)
  {}

  NodeStatus tick() override
  {
    const int allowed = getInput<int>("number_of_retries").value_or(1);
    setStatus(NodeStatus::RUNNING);
    while(recoveries_ <= allowed)
    {
      const NodeStatus result = children_nodes_[in_recovery_ ? 1 : 0]->executeTick();
      if(result == NodeStatus::RUNNING)
      {
        return result;
      }
      if(!in_recovery_)
      {
        if(result == NodeStatus::FAILURE && recoveries_ < allowed)
        {
          haltChild(0);
          in_recovery_ = true;
          continue;
        }
        halt();
        return result;  // SUCCESS, SKIPPED, or FAILURE with no recovery left
      }
      if(result == NodeStatus::SUCCESS)
      {
        haltChild(1);
        ++recoveries_;
        in_recovery_ = false;
        continue;
      }
      if(result == NodeStatus::SKIPPED)
      {
        haltChild(1);
        in_recovery_ = false;
        return NodeStatus::FAILURE;
      }
      halt();
      return NodeStatus::FAILURE;
    }
    halt();
    return NodeStatus::FAILURE;
  }

  void halt() override
  {
    BT::ControlNode::halt();
    recoveries_ = 0;
    in_recovery_ = false;
  }

private:
  int recoveries_ = 0;
  bool in_recovery_ = false;
};

class PipelineSequence : public BT::ControlNode
{
public:
  PipelineSequence(const std::string& name, const BT::NodeConfig& config)
    : BT::ControlNode(name, config)
  {}

  NodeStatus tick() override
  {
    for(size_t i = 0; i < childrenCount(); ++i)
    {
      const NodeStatus result = children_nodes_[i]->executeTick();
      if(result == NodeStatus::FAILURE)
      {
        halt();
        return result;
      }
      if(result == NodeStatus::RUNNING && i >= furthest_)
      {
        furthest_ = i;
        return result;
      }
    }
    halt();
    return NodeStatus::SUCCESS;
  }

  void halt() override
  {
    BT::ControlNode::halt();
    furthest_ = 0;
  }

private:
  size_t furthest_ = 0;
};

class RoundRobin : public BT::ControlNode
{
public:
  RoundRobin(const std::string& name, const BT::NodeConfig& config)
    : BT::ControlNode(name, config)
  {}

  NodeStatus tick() override
  {
    setStatus(NodeStatus::RUNNING);
    size_t skipped = 0;
    while(failed_ + skipped < childrenCount())
    {
      const NodeStatus result = children_nodes_[next_]->executeTick();
      if(result == NodeStatus::RUNNING)
      {
        return result;
      }
      next_ = (next_ + 1) % childrenCount();
      if(result == NodeStatus::SUCCESS)
      {
        failed_ = 0;
        haltChildren();
        return result;
      }
      (result == NodeStatus::FAILURE ? failed_ : skipped) += 1;
    }
    const bool all_skipped = skipped == childrenCount();
    halt();
    return all_skipped ? NodeStatus::SKIPPED : NodeStatus::FAILURE;
  }

  void halt() override
  {
    BT::ControlNode::halt();
    next_ = 0;
    failed_ = 0;
  }

private:
  size_t next_ = 0;
  size_t failed_ = 0;
};

class RateController : public BT::DecoratorNode
{
public:
  RateController(const std::string& name, const BT::NodeConfig& config)
    : BT::DecoratorNode(name, config)
  {}

  NodeStatus tick() override
  {
    using Clock = std::chrono::steady_clock;
    const bool starting = !BT::isStatusActive(status());
    if(starting)
    {
      last_ = Clock::now();
    }
    setStatus(NodeStatus::RUNNING);
    const double period = 1.0 / getInput<double>("hz").value_or(10.0);
    const std::chrono::duration<double> waited = Clock::now() - last_;
    if(!starting && child()->status() != NodeStatus::RUNNING && waited.count() < period)
    {
      return NodeStatus::RUNNING;
    }
    const NodeStatus result = child()->executeTick();
    if(result != NodeStatus::RUNNING)
    {
      resetChild();
    }
    if(result == NodeStatus::SUCCESS)
    {
      last_ = Clock::now();
    }
    return result;
  }

private:
  std::chrono::steady_clock::time_point last_;
};

class SingleTrigger : public BT::DecoratorNode
{
public:
  SingleTrigger(const std::string& name, const BT::NodeConfig& config)
    : BT::DecoratorNode(name, config)
  {}

  NodeStatus tick() override
  {
    if(!BT::isStatusActive(status()))
    {
      fired_ = false;
    }
    setStatus(NodeStatus::RUNNING);
    if(fired_)
    {
      return NodeStatus::FAILURE;
    }
    const NodeStatus result = child()->executeTick();
    fired_ = result == NodeStatus::SUCCESS || result == NodeStatus::FAILURE;
    return result;
  }

private:
  bool fired_ = false;
};

// The stand-in registered for a Nav2 model ID, or nullptr.
inline BT::NodeBuilder builderFor(const std::string& id)
{
  if(id == "RecoveryNode")
    return BT::CreateBuilder<RecoveryNode>();
  if(id == "PipelineSequence")
    return BT::CreateBuilder<PipelineSequence>();
  if(id == "RoundRobin")
    return BT::CreateBuilder<RoundRobin>();
  if(id == "RateController")
    return BT::CreateBuilder<RateController>();
  if(id == "SingleTrigger")
    return BT::CreateBuilder<SingleTrigger>();
  return nullptr;
}

}  // namespace nav2_standins
