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
// The five that read the robot or ROS messages run on a reduced, test-driven input
// (Robot below, set from the checker's command line; the Python side feeds the same):
//  - DistanceController: on starting, remember the robot's pose (none: FAILURE); tick the
//    child on the first tick, while it runs, and once the robot is `distance` metres from
//    where the child last succeeded; else RUNNING.
//  - SpeedController: tick the child on the first tick, when goal/goals changed, while it
//    runs, and once the period passed (then the period becomes 1/rate for the robot's
//    speed, linear from min_rate at min_speed to max_rate at max_speed); starting and a
//    new goal restart the period at 1/max_rate.
//  - GoalUpdatedController: tick the child on starting, when goal/goals changed, and while
//    it runs; else RUNNING.
//  - GoalUpdater: no goal is ever received here: output_goal is input_goal, then the child.
//  - PathLongerOnApproach: the checker has no nav_msgs/Path; the path is never replaced
//    by a longer one, so the child is never ticked and the node succeeds.
// "Changed" is read from the blackboard entry's sequence_id (a write to goal or goals).
#pragma once

#include <behaviortree_cpp/control_node.h>
#include <behaviortree_cpp/decorator_node.h>

#include <cmath>
#include <cstdint>
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

// The clock and the robot of the reduced form. `seconds` is the simulated time of the
// current tick ((tick - 1) * the time between ticks): the stand-ins' clock, so a rate or a
// period falls on the same tick on both sides, whatever the machine's load (Nav2's trees
// hold no BT.CPP timer node, so their checks need no sleeping). The robot moves along x at
// `speed` m/s; without `known`, there is no pose and the speed is 0.
struct Robot
{
  static inline bool known = false;
  static inline double speed = 0.0;
  static inline double seconds = 0.0;
  static double x() { return speed * seconds; }
};

class RateController : public BT::DecoratorNode
{
public:
  RateController(const std::string& name, const BT::NodeConfig& config)
    : BT::DecoratorNode(name, config)
  {}

  NodeStatus tick() override
  {
    const bool starting = !BT::isStatusActive(status());
    if(starting)
    {
      last_ = Robot::seconds;
    }
    setStatus(NodeStatus::RUNNING);
    const double period = 1.0 / getInput<double>("hz").value_or(10.0);
    const double waited = Robot::seconds - last_;
    if(!starting && child()->status() != NodeStatus::RUNNING && waited < period)
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
      last_ = Robot::seconds;
    }
    return result;
  }

private:
  double last_ = 0.0;
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

// How often the entry a port is remapped to was written (0: no entry).
inline uint64_t entryVersion(const BT::TreeNode& node, const std::string& port)
{
  const auto found = node.config().input_ports.find(port);
  const std::string remap = found == node.config().input_ports.end() ? "{=}" : found->second;
  const auto key = BT::TreeNode::getRemappedKey(port, remap);
  if(!key)
  {
    return 0;
  }
  const auto entry = node.config().blackboard->getEntry(std::string(key.value()));
  return entry ? entry->sequence_id + 1 : 0;
}

class DistanceController : public BT::DecoratorNode
{
public:
  DistanceController(const std::string& name, const BT::NodeConfig& config)
    : BT::DecoratorNode(name, config)
  {}

  NodeStatus tick() override
  {
    if(!Robot::known)
    {
      return NodeStatus::FAILURE;
    }
    if(!BT::isStatusActive(status()))
    {
      start_ = Robot::x();
      first_ = true;
    }
    setStatus(NodeStatus::RUNNING);
    const double here = Robot::x();
    const double distance = getInput<double>("distance").value_or(1.0);
    if(first_ || child()->status() == NodeStatus::RUNNING || std::abs(here - start_) >= distance)
    {
      first_ = false;
      const NodeStatus result = child()->executeTick();
      if(result == NodeStatus::SUCCESS)
      {
        start_ = here;
      }
      return result;
    }
    return NodeStatus::RUNNING;
  }

private:
  double start_ = 0.0;
  bool first_ = true;
};

class SpeedController : public BT::DecoratorNode
{
public:
  SpeedController(const std::string& name, const BT::NodeConfig& config)
    : BT::DecoratorNode(name, config)
  {}

  NodeStatus tick() override
  {
    const double now = Robot::seconds;
    const uint64_t goals = entryVersion(*this, "goal") * 1000003u + entryVersion(*this, "goals");
    const double max_rate = getInput<double>("max_rate").value_or(1.0);
    if(!BT::isStatusActive(status()) || goals != seen_)  // starting, or a new goal
    {
      period_ = 1.0 / max_rate;
      start_ = now;
      first_ = true;
      seen_ = goals;
    }
    setStatus(NodeStatus::RUNNING);
    const double elapsed = now - start_;
    if(first_ || child()->status() == NodeStatus::RUNNING || elapsed >= period_)
    {
      first_ = false;
      if(elapsed >= period_)
      {
        period_ = 1.0 / rate(Robot::known ? Robot::speed : 0.0, max_rate);
        start_ = now;
      }
      return child()->executeTick();
    }
    return NodeStatus::RUNNING;
  }

private:
  double rate(double speed, double max_rate)
  {
    const double min_rate = getInput<double>("min_rate").value_or(0.1);
    const double low = getInput<double>("min_speed").value_or(0.0);
    const double high = getInput<double>("max_speed").value_or(0.5);
    if(speed <= low || high == low)
      return min_rate;
    if(speed >= high)
      return max_rate;
    return min_rate + (max_rate - min_rate) * (speed - low) / (high - low);
  }

  double period_ = 1.0;
  double start_ = 0.0;
  bool first_ = true;
  uint64_t seen_ = 0;
};

class GoalUpdatedController : public BT::DecoratorNode
{
public:
  GoalUpdatedController(const std::string& name, const BT::NodeConfig& config)
    : BT::DecoratorNode(name, config)
  {}

  NodeStatus tick() override
  {
    const uint64_t goals = entryVersion(*this, "goal") * 1000003u + entryVersion(*this, "goals");
    if(!BT::isStatusActive(status()) || goals != seen_)
    {
      seen_ = goals;
      updated_ = true;
    }
    setStatus(NodeStatus::RUNNING);
    if(child()->status() == NodeStatus::RUNNING || updated_)
    {
      updated_ = false;
      return child()->executeTick();
    }
    return NodeStatus::RUNNING;
  }

private:
  uint64_t seen_ = 0;
  bool updated_ = true;
};

class GoalUpdater : public BT::DecoratorNode
{
public:
  GoalUpdater(const std::string& name, const BT::NodeConfig& config)
    : BT::DecoratorNode(name, config)
  {}

  NodeStatus tick() override
  {
    setStatus(NodeStatus::RUNNING);
    BT::Any goal;
    if(auto locked = getLockedPortContent("input_goal"); locked && !locked->empty())
    {
      goal = *locked.get();
    }
    if(!goal.empty())
    {
      if(auto out = getLockedPortContent("output_goal"))
      {
        out.assign(goal);
      }
    }
    return child()->executeTick();
  }
};

class PathLongerOnApproach : public BT::DecoratorNode
{
public:
  PathLongerOnApproach(const std::string& name, const BT::NodeConfig& config)
    : BT::DecoratorNode(name, config)
  {}

  NodeStatus tick() override
  {
    return NodeStatus::SUCCESS;
  }
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
  if(id == "DistanceController")
    return BT::CreateBuilder<DistanceController>();
  if(id == "SpeedController")
    return BT::CreateBuilder<SpeedController>();
  if(id == "GoalUpdatedController")
    return BT::CreateBuilder<GoalUpdatedController>();
  if(id == "GoalUpdater")
    return BT::CreateBuilder<GoalUpdater>();
  if(id == "PathLongerOnApproach")
    return BT::CreateBuilder<PathLongerOnApproach>();
  return nullptr;
}

}  // namespace nav2_standins
