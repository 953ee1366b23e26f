//! The temporal passes: achievers against the paper's table, partial orders whose every
//! linearisation is a valid plan, schedules checked by the timed validator, and the STN solver
//! against Floyd-Warshall on random networks.

mod common;

use common::{search, timed};

use std::time::{Duration, Instant};

use kbc::ir::plan::Plan;
use kbc::ir::pop::{Achiever, Pop};
use kbc::ir::schedule;
use kbc::ir::stn::{Edge, EdgeKind, Stn, TimePoint};
use kbc::ladder;
use kbc::passes;
use kbc::planner::{self, Budget, Options, SearchKind, Silent};
use kbc::session::{ReassignedMakespan, Session, Timed};
use kbc::validate::PlanStep;
use petgraph::graph::DiGraph;

/// The plan in a plan file, validated.
fn plan_file(session: &mut Session, path: &str, problem: usize) -> Plan {
    let file = session.read_file(path.as_ref()).expect("readable plan");
    let steps = session.read_plan_steps(file).expect("a plan file");
    let verdict = session.validate(problem, &steps);
    assert!(!verdict.diagnostics.has_errors(), "the plan file is valid");
    verdict.plan
}

/// The schedule as a timed plan, replayed by the timed validator.
fn assert_schedule_valid(session: &mut Session, timed: &Timed, times: &[i64]) {
    let kb = session.kb();
    let span = kb.problems[timed.pop.problem].span;
    let schedule = schedule::Schedule { earliest: times.to_vec(), latest: times.to_vec(), makespan: 0 };
    let steps: Vec<PlanStep> = schedule::timed_actions(kb, &timed.pop, &schedule)
        .into_iter()
        .map(|a| PlanStep { timing: Some((a.time, a.duration)), ..PlanStep::named(a.name, span) })
        .collect();
    let verdict = session.validate(timed.pop.problem, &steps);
    assert!(!verdict.diagnostics.has_errors(), "invalid schedule: {:?}", common::messages(&verdict.diagnostics));
}

#[test]
fn the_papers_example_reproduces_its_table_of_achievers() {
    let mut session = common::load(&["examples/06_partial_order/kb.pl"]);
    let plan = plan_file(&mut session, "examples/06_partial_order/plan.txt", 0);
    let timed = timed(&mut session, &plan);
    // The paper's table "List of achievers": a1 [a0], a2 [a1], a3 [a2], a4 [a0], a5 [a4],
    // a6 [a5], a7 [a6], a8 [a7, a3].
    let expected: [&[usize]; 8] = [&[0], &[1], &[2], &[0], &[4], &[5], &[6], &[3, 7]];
    for (i, want) in expected.iter().enumerate() {
        let got: Vec<usize> = timed
            .pop
            .achievers(i)
            .into_iter()
            .map(|a| match a {
                Achiever::Init => 0,
                Achiever::Step(j) => j + 1,
            })
            .collect();
        assert_eq!(&got, want, "achievers of a{}", i + 1);
    }
    // The two grip-and-move chains run in parallel: both grips at time 0, both moves one ε
    // after their grips end at 1.
    let at = |i: usize| timed.schedule.earliest[i];
    assert_eq!((at(0), at(3)), (0, 0));
    assert_eq!((at(2), at(5)), (1001, 1001));
    assert!(at(7) > at(6), "b2 lands after b1, on top of it");
    assert_schedule_valid(&mut session, &timed, &timed.schedule.earliest);
    assert_schedule_valid(&mut session, &timed, &timed.schedule.latest);
}

/// A random linearisation of `pop`'s partial order, from a linear congruential generator.
fn linearisation(pop: &Pop, seed: u64) -> Vec<usize> {
    let n = pop.steps.len();
    let mut before: Vec<Vec<usize>> = vec![Vec::new(); n];
    for o in &pop.orderings {
        before[o.after].push(o.before);
    }
    let mut done = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut random = seed;
    while order.len() < n {
        let ready: Vec<usize> = (0..n).filter(|&i| !done[i] && before[i].iter().all(|&b| done[b])).collect();
        random = random.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let pick = ready[(random >> 33) as usize % ready.len()];
        done[pick] = true;
        order.push(pick);
    }
    order
}

fn assert_linearisations_valid(session: &mut Session, plan: &Plan, timed: &Timed, samples: u64) {
    let span = session.kb().problems[plan.problem].span;
    for seed in 0..samples {
        let order = linearisation(&timed.pop, seed);
        let steps: Vec<PlanStep> = order.iter().map(|&i| PlanStep::named(plan.steps[i].name.clone(), span)).collect();
        let verdict = session.validate(plan.problem, &steps);
        assert!(
            !verdict.diagnostics.has_errors(),
            "linearisation {order:?} of the partial order is not a valid plan: {:?}",
            common::messages(&verdict.diagnostics)
        );
    }
}

#[test]
fn every_linearisation_of_a_partial_order_is_a_valid_plan() {
    let mut session = common::load(&["examples/01_paper_tests/tests.pl"]);
    for problem in 0..session.kb().problems.len() {
        let plan = search(&mut session, problem);
        let timed = timed(&mut session, &plan);
        assert_linearisations_valid(&mut session, &plan, &timed, 30);
        assert_schedule_valid(&mut session, &timed, &timed.schedule.earliest);
        assert_schedule_valid(&mut session, &timed, &timed.schedule.latest);
    }
    for rung in ladder::standard().into_iter().filter(|r| r.blocks <= 6) {
        let mut session = Session::from_text(&rung.name(), rung.source());
        let plan = search(&mut session, 0);
        let timed = timed(&mut session, &plan);
        assert_linearisations_valid(&mut session, &plan, &timed, 10);
        assert_schedule_valid(&mut session, &timed, &timed.schedule.earliest);
        assert_schedule_valid(&mut session, &timed, &timed.schedule.latest);
    }
}

#[test]
fn the_schedule_runs_arms_in_parallel() {
    let mut session = common::load(&["examples/02_llm_stacking/test_case.pl"]);
    let plan = search(&mut session, 0);
    let timed = timed(&mut session, &plan);
    let sequential: i64 = timed.stn.durations.iter().flatten().map(|b| b.min).sum();
    assert!(
        timed.schedule.makespan < sequential,
        "makespan {} is not below one action at a time ({sequential})",
        timed.schedule.makespan
    );
    assert_schedule_valid(&mut session, &timed, &timed.schedule.earliest);
}

/// No path in [`floyd_warshall`]'s matrix.
const INF: i64 = i64::MAX / 4;

/// Floyd-Warshall on a distance graph: `None` if there is a negative cycle, else the shortest
/// distance between every pair of nodes, by node index ([`INF`] where there is no path).
fn floyd_warshall(stn: &Stn) -> Option<Vec<Vec<i64>>> {
    let n = stn.graph.node_count();
    let mut d = vec![vec![INF; n]; n];
    for (i, row) in d.iter_mut().enumerate() {
        row[i] = 0;
    }
    for edge in stn.graph.raw_edges() {
        let (u, v) = (edge.source().index(), edge.target().index());
        d[u][v] = d[u][v].min(edge.weight.weight);
    }
    for k in 0..n {
        for i in 0..n {
            if d[i][k] == INF {
                continue;
            }
            for j in 0..n {
                if d[k][j] < INF && d[i][k] + d[k][j] < d[i][j] {
                    d[i][j] = d[i][k] + d[k][j];
                }
            }
        }
    }
    if (0..n).any(|i| d[i][i] < 0) {
        return None;
    }
    Some(d)
}

/// The earliest time of every point: minus its shortest distance to the origin.
fn floyd_warshall_earliest(stn: &Stn) -> Option<Vec<i64>> {
    let d = floyd_warshall(stn)?;
    let origin = stn.origin.index();
    Some(stn.nodes.iter().map(|node| -d[node.index()][origin]).collect())
}

/// A random network: `n` points after the origin, forward precedences and random durations,
/// some of them contradictory.
fn random_stn(n: usize, seed: u64) -> Stn {
    let mut random = seed.wrapping_mul(2654435761).wrapping_add(1);
    let mut next = move |bound: u64| {
        random = random.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (random >> 33) % bound.max(1)
    };
    let mut graph: DiGraph<TimePoint, Edge> = DiGraph::new();
    let origin = graph.add_node(TimePoint::Origin);
    let nodes: Vec<_> = (0..n).map(|i| graph.add_node(TimePoint::Step(i))).collect();
    for &node in &nodes {
        graph.add_edge(node, origin, Edge { weight: 0, kind: EdgeKind::AfterOrigin });
    }
    let precedence = |before, after| EdgeKind::Precedence { before, after, reason: kbc::ir::pop::Reason::StartEnd };
    for after in 1..n {
        for _ in 0..next(3) {
            let before = next(after as u64) as usize;
            let weight = -(next(3) as i64);
            graph.add_edge(nodes[after], nodes[before], Edge { weight, kind: precedence(before, after) });
        }
        if next(4) == 0 {
            // An upper bound back from a later point: may close a negative cycle.
            let start = next(after as u64) as usize;
            let weight = next(12) as i64;
            let source = kbc::ir::stn::DurationSource::Default;
            graph.add_edge(nodes[start], nodes[after], Edge { weight, kind: EdgeKind::MaxDuration { start, source } });
        }
    }
    Stn { graph, origin, nodes, durations: vec![None; n], epsilon: kbc::ir::stn::EPSILON }
}

#[test]
fn the_stn_solver_agrees_with_floyd_warshall() {
    let mut consistent = 0;
    let mut inconsistent = 0;
    for seed in 0..300 {
        let stn = random_stn(2 + (seed as usize % 25), seed);
        let reference = floyd_warshall_earliest(&stn);
        match (passes::schedule::solve(&stn), reference) {
            (Ok(schedule), Some(earliest)) => {
                assert_eq!(schedule.earliest, earliest, "seed {seed}");
                for i in 0..stn.nodes.len() {
                    assert!(schedule.latest[i] >= schedule.earliest[i], "seed {seed}");
                }
                consistent += 1;
            }
            (Err(cycle), None) => {
                assert!(cycle.weight < 0, "seed {seed}: a cycle of weight {}", cycle.weight);
                // The cycle closes: each edge ends where the next begins.
                for pair in cycle.edges.windows(2) {
                    let (_, end) = stn.graph.edge_endpoints(pair[0]).expect("an edge");
                    let (start, _) = stn.graph.edge_endpoints(pair[1]).expect("an edge");
                    assert_eq!(end, start, "seed {seed}");
                }
                inconsistent += 1;
            }
            (ours, reference) => panic!("seed {seed}: solver says {ours:?}, Floyd-Warshall {reference:?}"),
        }
    }
    assert!(consistent > 50 && inconsistent > 20, "{consistent} consistent, {inconsistent} inconsistent");
}

#[test]
fn the_minimal_network_agrees_with_floyd_warshall() {
    let mut checked = 0;
    for seed in 0..300 {
        let stn = random_stn(2 + (seed as usize % 25), seed);
        let (Ok(schedule), Some(d)) = (passes::schedule::solve(&stn), floyd_warshall(&stn)) else {
            continue;
        };
        let network = passes::schedule::MinimalNetwork::new(&stn, &schedule);
        for x in 0..stn.len() {
            let (later, earlier) = network.row(x);
            for y in 0..stn.len() {
                let expect = |d: i64| (d < INF).then_some(d);
                assert_eq!(later[y], expect(d[x][y]), "seed {seed}: t({y}) - t({x}) at most");
                assert_eq!(earlier[y], expect(d[y][x]), "seed {seed}: t({x}) - t({y}) at most");
            }
        }
        checked += 1;
    }
    assert!(checked > 50, "only {checked} consistent networks");
}

#[test]
fn improving_the_makespan_never_makes_it_longer() {
    let mut session = common::load(&["examples/02_llm_stacking/test_case.pl"]);
    let mut task = passes::task::build(session.kb(), 0);
    let budget = Budget { deadline: Some(Instant::now() + Duration::from_secs(60)), ..Budget::default() };
    let options = Options {
        search: SearchKind::Heuristic,
        max_depth: None,
        budget,
        plans: usize::MAX,
        improve: Some(Duration::from_millis(500)),
        ..Options::default()
    };
    let outcome = planner::search(session.kb(), session.interner(), &mut task, &options, &mut Silent);
    let first = outcome.result.expect("a plan");
    let first_makespan = timed(&mut session, &first).schedule.makespan;
    let mut best = first_makespan;
    for plan in &outcome.alternatives {
        let timed = timed(&mut session, plan);
        assert_schedule_valid(&mut session, &timed, &timed.schedule.earliest);
        best = best.min(timed.schedule.makespan);
    }
    assert!(best <= first_makespan);
    // Each plan the search reports has a shorter estimated makespan than the ones before. The
    // estimate ignores threat orderings, so the schedule can disagree with it, but on this case
    // (first plan 22 s, best known 14 s) a better plan comes out in well under 0.5 s even in a
    // debug build.
    if !outcome.alternatives.is_empty() {
        assert!(
            best < first_makespan,
            "{} alternatives, none shorter than {first_makespan}",
            outcome.alternatives.len()
        );
    }
}

/// A scorer that remembers every plan it was asked about.
struct Recording<'a> {
    inner: ReassignedMakespan<'a>,
    scored: Vec<(Plan, Option<i64>)>,
}

impl planner::Score for Recording<'_> {
    fn score(&mut self, task: &mut kbc::ir::task::Task, plan: &Plan) -> Option<i64> {
        let score = self.inner.score(task, plan);
        self.scored.push((plan.clone(), score));
        score
    }
}

#[test]
fn improving_with_a_scorer_keeps_the_plans_it_scores_shorter() {
    let rung = ladder::Rung { family: ladder::Family::Swap, blocks: 6, arms: 3, seed: 1 };
    let mut session = Session::from_text(&rung.name(), rung.source());
    let program = session.program(0);
    let (kb, interner) = (session.kb(), session.interner());
    let mut task = passes::task::build(kb, 0);
    // A budget of states, not of time, so that the run is the same on any machine.
    let options = Options {
        search: SearchKind::Heuristic,
        max_depth: None,
        budget: Budget { max_states: 2_000, ..Budget::default() },
        plans: 1,
        improve: Some(Duration::from_secs(600)),
        ..Options::default()
    };
    let mut recording =
        Recording { inner: ReassignedMakespan::new(kb, interner, &program, kbc::ir::stn::EPSILON), scored: vec![] };
    let outcome = planner::search_scored(kb, interner, &mut task, &options, Some(&mut recording), &mut Silent);
    // When the first plan came is known, and the improving went on after it.
    let first_found = outcome.stats.first_found.expect("a first plan, found at a known time");
    assert!(first_found <= outcome.stats.elapsed && outcome.stats.first_expanded < outcome.stats.expanded);
    let first = outcome.result.expect("a plan");
    let mut kept = vec![first];
    kept.extend(outcome.alternatives);
    let scored = recording.scored;
    // The plans kept are the first and then each one scored shorter than all before it.
    let mut best: Option<i64> = None;
    let mut expected = Vec::new();
    for (plan, score) in &scored {
        let score = score.expect("every plan of this rung can be scheduled");
        if best.is_none_or(|b| score < b) {
            best = Some(score);
            expected.push(plan.clone());
        }
    }
    assert_eq!(kept, expected);
    // Scores are the makespan `kbc plan` ends up with: scheduled, then reassigned.
    for plan in &kept {
        let scheduled = timed(&mut session, plan);
        let (_, reassigned) = session.reassign(plan.clone(), scheduled);
        let score = scored.iter().find(|(p, _)| p == plan).and_then(|(_, s)| *s);
        assert_eq!(score, Some(reassigned.schedule.makespan));
        assert_schedule_valid(&mut session, &reassigned, &reassigned.schedule.earliest);
    }
    // On this rung (the first plan 17.010 time units after reassigning and its detours) the
    // phase finds shorter ones within the budget (16.014 when written). (build_b06_a3_s1 was
    // the rung here until the shortcuts made its first plan 12 units long, its optimum;
    // build_b08_a3_s3 until the relocations that hold a move's end back made its first plan
    // as short as the phase found; build_b08_a3_s1 until the backward rules of `reassign`
    // did the same.)
    assert!(kept.len() >= 2, "nothing shorter than the first plan in {} states", options.budget.max_states);
}

/// The plan's step names with every unit name (arm) erased, sorted: what a plan does to the
/// world, apart from who does it and when.
fn without_units(session: &Session, plan: &Plan, units: &[&str]) -> Vec<String> {
    let no_vars = kbc::ir::hir::VarTable::default();
    let mut names: Vec<String> = plan
        .steps
        .iter()
        .map(|s| {
            let text = kbc::ir::hir::term_to_string(session.interner(), &s.name, &no_vars);
            let mut args: Vec<String> = text.split(['(', ',', ')']).map(|a| a.trim().to_string()).collect();
            for arg in &mut args {
                if units.contains(&arg.as_str()) {
                    *arg = "_".into();
                }
            }
            args.join(" ")
        })
        .collect();
    names.sort();
    names
}

/// The search's timeline of a whole plan, replayed: (makespan, resource-free makespan).
fn timeline_makespans(session: &mut Session, plan: &Plan) -> (i64, i64) {
    let program = session.program(plan.problem);
    let mut task = passes::task::build(session.kb(), plan.problem);
    let mut machine = kbc::engine::Machine::new(&program, Budget::default().engine_steps);
    let mut durations = planner::timing::Durations::default();
    let mut timeline = planner::timing::Timeline::default();
    let path = planner::path_of(&mut task, plan);
    assert_eq!(path.len(), plan.steps.len());
    let mut state = task.init.clone();
    for action in &path {
        // (Applying the step interns the facts it adds, which the timeline looks up.)
        state = planner::successors::apply(&mut task, &state, action);
        let placement = timeline.place(&mut task, &mut machine, &mut durations, action).expect("placed");
        timeline.record(&mut task, action, placement);
    }
    (timeline.makespan, timeline.free_makespan)
}

#[test]
fn reassigning_jobs_keeps_plans_valid_and_never_makes_them_longer() {
    let mut improved = Vec::new();
    let mut rungs: Vec<ladder::Rung> = ladder::standard().into_iter().filter(|r| r.blocks <= 12).collect();
    rungs.extend((2..5).map(|seed| ladder::Rung { family: ladder::Family::Swap, blocks: 8, arms: 3, seed }));
    rungs.extend((2..5).map(|seed| ladder::Rung { family: ladder::Family::Build, blocks: 8, arms: 4, seed }));
    for rung in rungs {
        let mut session = Session::from_text(&rung.name(), rung.source());
        let plan = search(&mut session, 0);
        let searched = timed(&mut session, &plan);
        let before = searched.schedule.makespan;
        let scheduled = timed(&mut session, &plan);
        let (again, _) = session.reassign_jobs(plan.clone(), scheduled);
        let (reassigned, kept) = session.reassign_jobs(plan.clone(), searched);
        assert_eq!(again, reassigned, "{}: the pass is deterministic", rung.name());
        assert!(kept.schedule.makespan <= before, "{}: longer after reassigning", rung.name());
        // The same steps, up to who does them.
        let arms: Vec<String> = (1..=rung.arms).map(|a| format!("a{a}")).collect();
        let arms: Vec<&str> = arms.iter().map(String::as_str).collect();
        assert_eq!(without_units(&session, &plan, &arms), without_units(&session, &reassigned, &arms));
        // Valid for the independent validator, as a total order, as a schedule, and in any
        // order its partial order allows.
        let span = session.kb().problems[0].span;
        let steps: Vec<PlanStep> = PlanStep::of_plan(session.kb(), &reassigned, span);
        let verdict = session.validate(0, &steps);
        assert!(!verdict.diagnostics.has_errors(), "{}: {:?}", rung.name(), common::messages(&verdict.diagnostics));
        let rescheduled = timed(&mut session, &reassigned);
        assert_eq!(kept.pop, rescheduled.pop, "{}: the partial order kept is the plan's", rung.name());
        assert_eq!(kept.schedule, rescheduled.schedule, "{}: the schedule kept is the plan's", rung.name());
        assert_schedule_valid(&mut session, &kept, &kept.schedule.earliest);
        assert_linearisations_valid(&mut session, &reassigned, &kept, 5);
        // The resource-free makespan the improvement phase prunes with is a lower bound for
        // the plan with its jobs given out again, and no more than the search's own estimate.
        let (estimate, free) = timeline_makespans(&mut session, &plan);
        assert!(free <= estimate, "{}: resource-free {free} above {estimate}", rung.name());
        assert!(free <= kept.schedule.makespan, "{}: {free} is no bound for {}", rung.name(), kept.schedule.makespan);
        if kept.schedule.makespan < before {
            improved.push(format!("{} {} -> {}", rung.name(), before, kept.schedule.makespan));
        }
    }
    println!("shorter after reassigning: {improved:#?}");
    // It pays on most rungs: 19 of these 30 when it was written.
    assert!(improved.len() >= 10, "only {} plans got shorter", improved.len());
}

/// Every candidate `reassign` makes (with the variants of its urgent rules) is a plan the
/// independent validator accepts, not only the one kept: the pass keeps every ordering of the partial order that does not come from a
/// unit's resource fact, and a pair of steps ordered for a resource fact may be ordered for
/// another fact too (`release_end(a1, b1)` gives a1 back and makes b1 clear; when a1 grips
/// b1 next, dropping the pair for the arm lost the block). Candidates that broke such links
/// were rejected one by one and hid better ones (reverse_b75_a10_s2: 121 -> 85 once fixed).
#[test]
fn every_reassign_candidate_is_a_valid_plan() {
    let mut rungs: Vec<ladder::Rung> = ladder::standard().into_iter().filter(|r| r.blocks <= 12).collect();
    for seed in 2..4 {
        rungs.extend(ladder::standard().into_iter().filter(|r| r.blocks <= 12).map(|r| ladder::Rung { seed, ..r }));
    }
    let mut checked = 0;
    for rung in rungs {
        let mut session = Session::from_text(&rung.name(), rung.source());
        let plan = search(&mut session, 0);
        // The search's plan and what the default run makes of it: both have candidates.
        let searched = timed(&mut session, &plan);
        let (rearranged, _) = session.reassign(plan.clone(), searched);
        for plan in [plan, rearranged] {
            let timed = timed(&mut session, &plan);
            for candidate in passes::reassign::candidates(
                session.kb(),
                &plan,
                &timed.pop,
                &timed.stn,
                passes::reassign::Rules::WithVariants(2),
            )
            .iter()
            {
                let span = session.kb().problems[0].span;
                let verdict = session.validate(0, &PlanStep::of_plan(session.kb(), &candidate.plan(), span));
                assert!(
                    !verdict.diagnostics.has_errors(),
                    "{}: {:?}",
                    rung.name(),
                    common::messages(&verdict.diagnostics)
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 100, "only {checked} candidates");
}

#[test]
fn reassigning_needs_a_renewable_resource_and_every_unit_in_a_job() {
    let rung = ladder::Rung { family: ladder::Family::Build, blocks: 6, arms: 3, seed: 1 };
    let mut session = Session::from_text(&rung.name(), rung.source());
    let plan = search(&mut session, 0);
    let timed = timed(&mut session, &plan);
    assert!(
        !passes::reassign::candidates(session.kb(), &plan, &timed.pop, &timed.stn, passes::reassign::Rules::Fixed)
            .is_empty(),
        "with `resources(available(_))` the pass has candidates"
    );
    // Without `resources(available(_))`, its actions imply it (grip_start deletes the
    // `available(A)` it needs, release_end adds it): the same jobs.
    let mut kb = session.kb().clone();
    kb.resources.clear();
    let steps = |kb: &kbc::ir::hir::Kb| -> Vec<Vec<usize>> {
        passes::reassign::jobs(kb, &plan).expect("jobs").steps().map(<[usize]>::to_vec).collect()
    };
    assert_eq!(steps(&kb), steps(session.kb()));
    // A start that deletes `available(A)` without needing it does not take a unit: nothing
    // is implied, and the pass has nothing to do.
    let available = session.interner().get("available");
    for action in &mut kb.actions {
        action.valid.retain(|v| v.term.callable().map(|(name, _)| name) != available);
    }
    assert!(
        passes::reassign::candidates(&kb, &plan, &timed.pop, &timed.stn, passes::reassign::Rules::Fixed).is_empty()
    );
    // An arm that grips a block in the initial state works before any job takes it: the pass
    // leaves such plans alone.
    let mut held = Session::from_text(
        "held.pl",
        "held :- go([available(a2), available(a3), gripped(a1, b1), ontable(b1, 1, 1), ontable(b2, 2, 2), \
         clear(b2), ontable(b3, 4, 1), clear(b3)], [ontable(b1, 3, 3), on(b2, b1, 3, 3), on(b3, b2, 3, 3), \
         available(a1), available(a2), available(a3)]).",
    );
    assert!(!held.has_errors(), "{:?}", common::messages(held.diagnostics()));
    let plan = search(&mut held, 0);
    assert!(plan.steps.iter().any(|s| kbc::ir::hir::term_to_string(held.interner(), &s.name, &Default::default())
        == "move_block_start(a1, b1, 1, 1, 3, 3)"));
    let timed = common::timed(&mut held, &plan);
    assert!(
        passes::reassign::candidates(held.kb(), &plan, &timed.pop, &timed.stn, passes::reassign::Rules::Fixed)
            .is_empty()
    );
}

/// A resource whose template no action changes (the grid rungs' `resources(agent(_))`, with
/// `agent(a1).` facts in the KB) is taken and given back through its units' one-argument facts
/// that effects delete and add (`free(a1)`): each job is a move's start and end, and the pass
/// rearranges the plan. Without those facts (a unit never taken), it leaves the plan alone.
#[test]
fn a_static_resource_template_makes_jobs_of_its_units_free_facts() {
    let rung = ladder::Rung { family: ladder::Family::Grid, blocks: 10, arms: 2, seed: 1 };
    let mut session = Session::from_text(&rung.name(), rung.source());
    let plan = search(&mut session, 0);
    let jobs = passes::reassign::jobs(session.kb(), &plan).expect("jobs");
    let steps: Vec<&[usize]> = jobs.steps().collect();
    assert_eq!(steps.len() * 2, plan.steps.len(), "a job per move");
    assert!(steps.iter().all(|s| s.len() == 2), "{steps:?}");
    let timed = timed(&mut session, &plan);
    assert!(
        !passes::reassign::candidates(session.kb(), &plan, &timed.pop, &timed.stn, passes::reassign::Rules::Fixed)
            .is_empty()
    );
    // `busy(A)` added instead of `free(A)` deleted: no step takes a unit, so no jobs.
    let source = rung.source().replace("del(free(A))", "add(busy(A))");
    let mut session = Session::from_text(&rung.name(), &source);
    assert!(!session.has_errors(), "{:?}", common::messages(session.diagnostics()));
    let plan = search(&mut session, 0);
    assert!(passes::reassign::jobs(session.kb(), &plan).is_none());
}

/// A pick-and-place KB in the style of an LLM pipeline, with no `resources/1`: agents
/// (`free/1`) pick a box from a cell and place it on a free one, as two durative actions. Box
/// `k` stands on cell `k` of a 4 x 3 grid and goes to cell `(k * 5) % 12`, so boxes queue for
/// each other's cells.
fn pick_and_place(declared: bool) -> String {
    pick_and_place_timed(declared, "duration(pick(_, _, _, _), 2, 3).")
}

/// [`pick_and_place`] with `pick` durations of its own.
fn pick_and_place_timed(declared: bool, pick: &str) -> String {
    let cells: Vec<(usize, usize)> = (1..=4).flat_map(|x| (1..=3).map(move |y| (x, y))).collect();
    let mut text = String::from(
        "agent(r1). agent(r2). agent(r3).
action(pick_start(R, B, X, Y), [free(R), at(B, X, Y)], [], [], [agent(R)],
    [del(free(R)), del(at(B, X, Y)), add(picking(R, B, X, Y))]).
action(pick_end(R, B, X, Y), [picking(R, B, X, Y)], [], [], [],
    [del(picking(R, B, X, Y)), add(holding(R, B)), add(empty(X, Y))]).
action(place_start(R, B, X, Y), [holding(R, B), empty(X, Y)], [], [], [],
    [del(holding(R, B)), del(empty(X, Y)), add(placing(R, B, X, Y))]).
action(place_end(R, B, X, Y), [placing(R, B, X, Y)], [], [], [],
    [del(placing(R, B, X, Y)), add(at(B, X, Y)), add(free(R))]).
duration(place(_, _, _, _), 2, 3).
",
    );
    text.push_str(pick);
    text.push('\n');
    if declared {
        text.push_str("resources(free(_)).\n");
    }
    let boxes = 9;
    let mut init: Vec<String> = (1..=3).map(|r| format!("free(r{r})")).collect();
    init.extend((0..boxes).map(|k| format!("at(box{k}, {}, {})", cells[k].0, cells[k].1)));
    init.extend(cells[boxes..].iter().map(|(x, y)| format!("empty({x}, {y})")));
    let goal: Vec<String> =
        (0..boxes).map(|k| format!("at(box{k}, {}, {})", cells[(k * 5) % 12].0, cells[(k * 5) % 12].1)).collect();
    text.push_str(&format!("move_boxes :- go([{}], [{}]).\n", init.join(", "), goal.join(", ")));
    text
}

/// A KB that declares no resource still has its plans rearranged, through the resource its
/// actions imply (`free/1`): as short as with `resources(free(_))` declared, shorter than the
/// search's plan, and valid. Its agents are alike in the initial state, so the search treats
/// them as one resource too; agents that the durations tell apart are kept apart there, and
/// their plans are still rearranged.
#[test]
fn a_kb_without_resources_is_reassigned_through_the_resource_its_actions_imply() {
    let settings = kbc::session::PlanSettings::default();
    let units_in_search = |session: &mut Session| session.task(0).schemas.iter().any(|s| !s.resource_vars.is_empty());
    let mut implied = Session::from_text("implied.pl", pick_and_place(false));
    assert!(!implied.has_errors(), "{:?}", common::messages(implied.diagnostics()));
    assert!(units_in_search(&mut implied), "the agents are alike: one resource for the search");
    let plan = search(&mut implied, 0);
    let jobs = passes::reassign::jobs(implied.kb(), &plan).expect("jobs through free/1");
    assert_eq!(jobs.steps().count() * 4, plan.steps.len(), "a job per box: pick and place");
    let (makespan, origin) = planned_makespan(&mut implied, "implied", &settings);
    assert!(origin.contains("jobs reassigned"), "{origin}");
    let unassigned = kbc::session::PlanSettings { reassign: false, ..settings.clone() };
    let (searched, _) = planned_makespan(&mut implied, "no reassign", &unassigned);
    assert!(makespan < searched, "{makespan} against the search's {searched}");
    let mut declared = Session::from_text("declared.pl", pick_and_place(true));
    let (with_declared, _) = planned_makespan(&mut declared, "declared", &settings);
    assert_eq!(makespan, with_declared);
    // r1 picks in one unit, the others in two: no longer alike.
    let durations = "speed(r1, 1). speed(r2, 2). speed(r3, 2).\nduration(pick(R, _, _, _), D, D) :- speed(R, D).";
    let mut apart = Session::from_text("apart.pl", pick_and_place_timed(false, durations));
    assert!(!apart.has_errors(), "{:?}", common::messages(apart.diagnostics()));
    assert!(!units_in_search(&mut apart), "the agents are told apart: no resource for the search");
    let (_, origin) = planned_makespan(&mut apart, "apart", &settings);
    assert!(origin.contains("jobs reassigned"), "{origin}");
}

/// The number of steps of `plan` whose names start with `prefix`.
fn count_steps(session: &Session, plan: &Plan, prefix: &str) -> usize {
    let no_vars = kbc::ir::hir::VarTable::default();
    let interner = session.interner();
    plan.steps.iter().filter(|s| kbc::ir::hir::term_to_string(interner, &s.name, &no_vars).starts_with(prefix)).count()
}

/// The search's plan for a problem, reassigning alone's plan and schedule, and what
/// `rearrange` (a pass of `Session`'s) makes of the plan, checked: the same each time, never
/// longer than reassigning alone, valid for the independent validator, as a total order, as a
/// schedule and in orders its partial order allows, and the schedule kept the plan's own.
#[allow(clippy::type_complexity)]
fn rearranged_checked(
    session: &mut Session,
    name: &str,
    rearrange: fn(&mut Session, Plan, Timed) -> (Plan, Timed),
) -> (Plan, (Plan, Timed), (Plan, Timed)) {
    let plan = search(session, 0);
    let searched = timed(session, &plan);
    let jobs = session.reassign_jobs(plan.clone(), searched);
    let searched = timed(session, &plan);
    let (rearranged, kept) = rearrange(session, plan.clone(), searched);
    let searched = timed(session, &plan);
    let (again, _) = rearrange(session, plan.clone(), searched);
    assert_eq!(again, rearranged, "{name}: deterministic");
    assert!(kept.schedule.makespan <= jobs.1.schedule.makespan, "{name}: longer than reassigning alone");
    let span = session.kb().problems[0].span;
    let verdict = session.validate(0, &PlanStep::of_plan(session.kb(), &rearranged, span));
    assert!(!verdict.diagnostics.has_errors(), "{name}: {:?}", common::messages(&verdict.diagnostics));
    let rescheduled = timed(session, &rearranged);
    assert_eq!(kept.schedule, rescheduled.schedule, "{name}: the schedule kept is the plan's");
    assert_schedule_valid(session, &kept, &kept.schedule.earliest);
    assert_linearisations_valid(session, &rearranged, &kept, 3);
    (plan, jobs, (rearranged, kept))
}

#[test]
fn sending_waiting_starts_aside_keeps_plans_valid_and_shortens_them() {
    // The search takes blocks straight to their goal places and the arms wait there, holding
    // them, until the places are ready; detours put such a block down on a free cell and
    // finish the move later, and `reassign` hands the freed arm other jobs.
    let mut shorter = Vec::new();
    // (rung, the name of a move's start, the steps a detour adds: a grip, a move and a release
    // in the standard blocks world; a move in the grid KBs, whose job is the move alone)
    let mut rungs: Vec<(ladder::Rung, &str, usize)> = Vec::new();
    for family in [ladder::Family::Swap, ladder::Family::Build] {
        for (blocks, arms) in [(6, 3), (10, 4), (15, 4)] {
            rungs.extend((1..3).map(|seed| (ladder::Rung { family, blocks, arms, seed }, "move_block_start", 6)));
        }
    }
    rungs.extend(ladder::grid().into_iter().take(3).map(|rung| (rung, "move_start", 2)));
    for (rung, start, size) in rungs {
        let name = rung.name();
        let mut session = Session::from_text(&name, rung.source());
        let (plan, (jobs_plan, jobs), (detoured, kept)) = rearranged_checked(&mut session, &name, Session::detour);
        // A detour is one more job for each start sent aside, and nothing else changes in
        // number.
        let moves = |p: &Plan| count_steps(&session, p, start);
        let extra = moves(&detoured) - moves(&plan);
        assert_eq!(detoured.steps.len(), plan.steps.len() + size * extra, "{name}");
        if extra == 0 {
            // Without a detour, the plan is reassign's, or relocated (fewer arms held) and then
            // shorter.
            assert!(
                detoured == jobs_plan || kept.schedule.makespan < jobs.schedule.makespan,
                "{name}: a plan changed that does not pay"
            );
        } else {
            assert!(kept.schedule.makespan < jobs.schedule.makespan, "{name}: a detour kept that does not pay");
            shorter.push(format!("{name} {} -> {} ({extra} aside)", jobs.schedule.makespan, kept.schedule.makespan));
        }
    }
    println!("shorter with detours: {shorter:#?}");
    // It pays on about half of these rungs (8 of 15 when written, swap_b10_a4_s1 56.044 ->
    // 31.021).
    assert!(shorter.len() >= 6, "only {} plans got shorter", shorter.len());
}

#[test]
fn merging_jobs_keeps_plans_valid_and_shortens_them() {
    // Where the search (or a detour) puts a block aside and another arm takes it on soon
    // after, one arm can carry it straight to the second place: one grip, move and release
    // fewer. Merges run after the detours, so a plan with them is never longer than one with
    // detours alone; on swap rungs they pay often.
    let mut shorter = Vec::new();
    // Of those, the plans with fewer moves (a detour in a later cycle may add one back).
    let mut fewer = 0;
    for (blocks, arms) in [(5, 3), (6, 3), (8, 3), (10, 4), (12, 4)] {
        for seed in 1..3 {
            let rung = ladder::Rung { family: ladder::Family::Swap, blocks, arms, seed };
            let name = rung.name();
            let mut session = Session::from_text(&name, rung.source());
            let (_, _, (detoured, without)) = rearranged_checked(&mut session, &name, Session::detour);
            let (_, _, (merged, with)) = rearranged_checked(&mut session, &name, Session::reassign);
            assert!(with.schedule.makespan <= without.schedule.makespan, "{name}: longer with merges");
            if with.schedule.makespan < without.schedule.makespan {
                let moves = |p: &Plan| count_steps(&session, p, "move_block_start");
                fewer += (moves(&merged) < moves(&detoured)) as usize;
                shorter.push(format!(
                    "{name} {} -> {} ({} -> {} moves)",
                    without.schedule.makespan,
                    with.schedule.makespan,
                    moves(&detoured),
                    moves(&merged)
                ));
            }
        }
    }
    println!("shorter with merges: {shorter:#?}");
    // When written: 9 of the 10, each with fewer moves (swap_b05_a3_s1 16.010 -> 14.010, 9 ->
    // 8; all 10 before the reserving rule of `passes::reassign`).
    assert!(shorter.len() >= 5, "only {} plans got shorter: {shorter:?}", shorter.len());
    assert!(2 * fewer >= shorter.len(), "only {fewer} shorter plans have fewer moves: {shorter:?}");
}

#[test]
fn a_merge_back_onto_the_cell_a_block_left_does_not_spoil_the_others() {
    // On build rungs a block that starts on a goal cell, under the place the goal gives it,
    // goes aside and comes back to that cell; its two jobs cannot be one (a move changes the
    // cell). Offered among the merges, it failed each set it was in and took the good merges
    // down with it (build_b12_a4_s3: 23.015 with all passes before, 21.013 after).
    let rung = ladder::Rung { family: ladder::Family::Build, blocks: 12, arms: 4, seed: 3 };
    let name = rung.name();
    let mut session = Session::from_text(&name, rung.source());
    let (_, _, (_, without)) = rearranged_checked(&mut session, &name, Session::detour);
    let (_, _, (_, with)) = rearranged_checked(&mut session, &name, Session::reassign);
    assert!(
        with.schedule.makespan < without.schedule.makespan,
        "{name}: merges made nothing shorter ({} -> {})",
        without.schedule.makespan,
        with.schedule.makespan
    );
}

/// The least total duration of a plan's moves (grid cells apart plus one, as std/blocks.pl
/// bounds `move_block`), read from the step names.
fn least_move_work(session: &Session, plan: &Plan) -> i64 {
    let no_vars = kbc::ir::hir::VarTable::default();
    let interner = session.interner();
    plan.steps
        .iter()
        .map(|s| kbc::ir::hir::term_to_string(interner, &s.name, &no_vars))
        .filter(|name| name.starts_with("move_block_start("))
        .map(|name| {
            let inner = &name["move_block_start(".len()..name.len() - 1];
            let cells: Vec<i64> = inner.split(", ").skip(2).map(|v| v.parse().expect("a cell")).collect();
            (cells[0] - cells[2]).abs() + (cells[1] - cells[3]).abs() + 1
        })
        .sum()
}

#[test]
fn relocating_shortens_a_swap_that_reassigning_alone_leaves() {
    // The search sends blocks aside onto far cells; relocating sends them to cheaper ones,
    // and the plan, reassigned, is shorter than reassigning alone makes it. (This test once
    // claimed that on swap_b20_a4_s3 every replay failed until the plan's places were
    // protected; that was no longer so before the backward rules of `reassign`. In a build
    // that reported it, of the 416 rungs of seeds 1-8 `kbc plan` reaches the protection on
    // reverse_b100_a10_s5, where the protected replay relocates 14 starts, and on a few where
    // it relocates none (reverse_b20_a4_s7, grid_b10_a2_s3): no test covers it now.)
    let rung = ladder::Rung { family: ladder::Family::Swap, blocks: 12, arms: 4, seed: 1 };
    let name = rung.name();
    let mut session = Session::from_text(&name, rung.source());
    let (plan, (_, jobs), (relocated, kept)) = rearranged_checked(&mut session, &name, Session::relocate);
    assert_ne!(relocated, plan, "{name}: nothing relocated");
    assert!(
        kept.schedule.makespan < jobs.schedule.makespan,
        "{name}: {} is no shorter than {}",
        kept.schedule.makespan,
        jobs.schedule.makespan
    );
}

/// The six snap actions of one cycle of arm a1 (grip, move, release) taking `block` from cell
/// `from` to cell `to`, as a plan file names them.
fn cycle(block: &str, (x1, y1): (i64, i64), (x2, y2): (i64, i64)) -> Vec<String> {
    let args = format!("a1, {block}, {x1}, {y1}, {x2}, {y2}");
    vec![
        format!("grip_start(a1, {block})"),
        format!("grip_end(a1, {block})"),
        format!("move_block_start({args})"),
        format!("move_block_end({args})"),
        format!("release_start(a1, {block})"),
        format!("release_end(a1, {block})"),
    ]
}

/// A session on the standard blocks world with the table `cells` and one problem, `name`,
/// from `init` to `goal` (arm a1 available in both).
fn one_arm_problem(name: &str, cells: &[(i64, i64)], init: &str, goal: &str) -> Session {
    let mut text: String = cells.iter().map(|(x, y)| format!("cell({x}, {y}).\n")).collect();
    text.push_str(&format!("{name} :- go(\n  [available(a1), {init}],\n  [available(a1), {goal}]\n).\n"));
    Session::from_text(&format!("{name}.pl"), text)
}

/// The plan of `steps` (a plan file's lines, numbered here), read and validated.
fn read_plan(session: &mut Session, steps: &[String]) -> Plan {
    let text: String = steps.iter().enumerate().map(|(i, s)| format!("{} {s}\n", i + 1)).collect();
    let file = session.add_text("hand.plan", text);
    let steps = session.read_plan_steps(file).expect("a plan file");
    let verdict = session.validate(0, &steps);
    assert!(!verdict.diagnostics.has_errors(), "{:?}", common::messages(&verdict.diagnostics));
    verdict.plan
}

/// The names of `plan`'s moves of blocks (their starts).
fn move_starts(session: &Session, plan: &Plan) -> Vec<String> {
    let no_vars = kbc::ir::hir::VarTable::default();
    plan.steps
        .iter()
        .map(|s| kbc::ir::hir::term_to_string(session.interner(), &s.name, &no_vars))
        .filter(|name| name.starts_with("move_block_start("))
        .collect()
}

/// The cells of a table five wide and two deep.
fn five_by_two() -> Vec<(i64, i64)> {
    (1..=5).flat_map(|x| (1..=2).map(move |y| (x, y))).collect()
}

#[test]
fn a_shortcut_leaves_a_block_where_it_was_until_its_last_move() {
    // b goes from (1,1) to (4,1). The plan puts it down on (2,2) first, for nothing: no other
    // block needs (1,1). The shortcut leaves that stop out: one move, straight there.
    let mut session =
        one_arm_problem("stop", &five_by_two(), "ontable(b, 1, 1), clear(b)", "ontable(b, 4, 1), clear(b)");
    let steps = [cycle("b", (1, 1), (2, 2)), cycle("b", (2, 2), (4, 1))].concat();
    let plan = read_plan(&mut session, &steps);
    let before = timed(&mut session, &plan).schedule.makespan;
    let searched = timed(&mut session, &plan);
    let (cut, kept) = session.shortcut(plan, searched);
    assert_eq!(move_starts(&session, &cut), ["move_block_start(a1, b, 1, 1, 4, 1)"]);
    // Grip, a move of three cells and a release: 1 + 4 + 1, with the separations.
    assert!(kept.schedule.makespan < before, "{} is no shorter than {before}", kept.schedule.makespan);
    assert_eq!(kept.schedule.makespan / 1000, 6, "{}", kept.schedule.makespan);
}

#[test]
fn a_shortcut_is_not_taken_where_another_block_needs_the_place_meanwhile() {
    // As above, but c moves onto (1,1), its goal cell, after b has left it and before b's
    // last move: b had to leave, and the plan stays as it is (a shortcut would keep c out).
    let (init, goal) = (
        "ontable(b, 1, 1), clear(b), ontable(c, 1, 2), clear(c)",
        "ontable(b, 4, 1), clear(b), ontable(c, 1, 1), clear(c)",
    );
    let mut session = one_arm_problem("needed", &five_by_two(), init, goal);
    let steps = [cycle("b", (1, 1), (2, 2)), cycle("c", (1, 2), (1, 1)), cycle("b", (2, 2), (4, 1))].concat();
    let plan = read_plan(&mut session, &steps);
    let searched = timed(&mut session, &plan);
    let (cut, _) = session.shortcut(plan.clone(), searched);
    assert_eq!(move_starts(&session, &cut), move_starts(&session, &plan));
}

#[test]
fn shortcuts_keep_plans_valid_and_shorten_build_plans() {
    // The search (and the detours) put blocks down on free cells on their way to the towers;
    // where nothing needed the cell they left, a shortcut keeps them there and saves a cycle.
    let mut shorter = Vec::new();
    for (blocks, arms) in [(6, 3), (8, 3), (10, 4), (12, 4)] {
        for seed in 1..4 {
            let rung = ladder::Rung { family: ladder::Family::Build, blocks, arms, seed };
            let name = rung.name();
            let mut session = Session::from_text(&name, rung.source());
            let (_, (jobs_plan, jobs), (cut, kept)) = rearranged_checked(&mut session, &name, Session::shortcut);
            let moves = |p: &Plan| count_steps(&session, p, "move_block_start");
            if kept.schedule.makespan < jobs.schedule.makespan {
                assert!(moves(&cut) < moves(&jobs_plan), "{name}: shorter without fewer moves");
                shorter.push(format!("{name} {} -> {}", jobs.schedule.makespan, kept.schedule.makespan));
            } else {
                assert_eq!(cut, jobs_plan, "{name}: a plan changed that does not pay");
            }
        }
    }
    println!("shorter with shortcuts: {shorter:#?}");
    assert!(!shorter.is_empty(), "no plan got shorter");
}

#[test]
fn relocating_a_block_aside_counts_its_way_on_from_there() {
    // b stands on a at (3,1) and both go to (5,1): b is put aside while a moves. The plan
    // puts it on (2,1); (4,1) is as near, and on the way: the relocation takes the cell whose
    // move there and move on from there cost least together, not the first of the nearest.
    let (init, goal) = ("ontable(a, 3, 1), on(b, a, 3, 1), clear(b)", "ontable(a, 5, 1), on(b, a, 5, 1), clear(b)");
    let mut session = one_arm_problem("aside", &five_by_two(), init, goal);
    let steps = [cycle("b", (3, 1), (2, 1)), cycle("a", (3, 1), (5, 1)), cycle("b", (2, 1), (5, 1))].concat();
    let plan = read_plan(&mut session, &steps);
    let before = timed(&mut session, &plan).schedule.makespan;
    let searched = timed(&mut session, &plan);
    let (relocated, kept) = session.relocate(plan.clone(), searched);
    let moves = move_starts(&session, &relocated);
    assert!(moves.contains(&"move_block_start(a1, b, 3, 1, 4, 1)".to_string()), "{moves:#?}");
    assert!(moves.contains(&"move_block_start(a1, b, 4, 1, 5, 1)".to_string()), "{moves:#?}");
    assert!(kept.schedule.makespan < before, "{} is no shorter than {before}", kept.schedule.makespan);
}

#[test]
fn relocating_a_block_aside_twice_moves_it_on_from_where_it_was_relocated() {
    // b stands on a at (3,1) and both go to (5,1). The plan puts b aside on (1,2), far off,
    // moves it on to (2,2), another buffer cell, and only then moves a and puts b on it.
    // Both of b's trips aside are relocatable, and the second leaves from where the first
    // went: once the first goes elsewhere, the second must take b from there. (It looked for
    // b on (1,2), found no move, and the first relocation was banned.)
    let (init, goal) = ("ontable(a, 3, 1), on(b, a, 3, 1), clear(b)", "ontable(a, 5, 1), on(b, a, 5, 1), clear(b)");
    let mut session = one_arm_problem("twice", &five_by_two(), init, goal);
    let steps = [
        cycle("b", (3, 1), (1, 2)),
        cycle("b", (1, 2), (2, 2)),
        cycle("a", (3, 1), (5, 1)),
        cycle("b", (2, 2), (5, 1)),
    ]
    .concat();
    let plan = read_plan(&mut session, &steps);
    let before = timed(&mut session, &plan).schedule.makespan;
    let searched = timed(&mut session, &plan);
    let (relocated, kept) = session.relocate(plan.clone(), searched);
    let moves: Vec<String> =
        move_starts(&session, &relocated).into_iter().filter(|m| m.starts_with("move_block_start(a1, b")).collect();
    // Three trips of b still, each from where the one before left it, and none to (1,2).
    assert_eq!(moves.len(), 3, "{moves:#?}");
    let cells: Vec<Vec<i64>> = moves
        .iter()
        .map(|name| name[..name.len() - 1].split(", ").skip(2).map(|v| v.parse().expect("a cell")).collect())
        .collect();
    for pair in cells.windows(2) {
        assert_eq!(pair[0][2..], pair[1][..2], "{moves:#?}");
    }
    assert!(cells.iter().all(|c| c[2..] != [1, 2]), "{moves:#?}");
    assert!(kept.schedule.makespan < before, "{} is no shorter than {before}", kept.schedule.makespan);
}

/// A move's least duration, as std/blocks.pl gives it (the distance and one), for the
/// relocations' `cost` (the action index unused: every move is one action).
fn least_move_duration(_: usize, name: &kbc::ir::hir::Term) -> i64 {
    let cells: Vec<i64> = name.args()[2..]
        .iter()
        .filter_map(|t| match t {
            kbc::ir::hir::Term::Int(v) => Some(*v),
            _ => None,
        })
        .collect();
    ((cells[0] - cells[2]).abs() + (cells[1] - cells[3]).abs() + 1) * kbc::ir::stn::UNITS
}

/// `rewrite` (a function of `planner::detour`) run on a task of `session`'s problem built
/// afresh, with a generator of its applicable actions.
fn rewritten<R>(
    session: &Session,
    rewrite: impl FnOnce(&mut planner::successors::Successors<'_>, &mut kbc::ir::task::Task) -> R,
) -> R {
    let mut task = passes::task::build(session.kb(), 0);
    let program = planner::program_for(session.kb(), session.interner(), 0);
    let mut successors = planner::successors::Successors::new(&task, kbc::engine::Machine::new(&program, 1_000_000));
    rewrite(&mut successors, &mut task)
}

#[test]
fn relocating_by_regret_gives_a_place_to_the_start_that_loses_most_without_it() {
    // One row of seven cells: p and q trade cells 1 and 2, r and s cells 4 and 5; cells 3, 6
    // and 7 are the goal's empty ones. The plan puts r aside on 7 and then p on 6, both far.
    // Cell 3 is the best place for both (r: from 4 to 3 and on to 5, 2 + 3 units of moving;
    // p: from 1 to 3 and on to 2, 3 + 2), but r does as well on 6 (3 + 2) while p's next best
    // is 6 (6 + 5). In the plan's order r, first, takes 3 and p stays on 6; by regret p
    // gets 3 and r goes to 6.
    let cells: Vec<(i64, i64)> = (1..=7).map(|x| (x, 1)).collect();
    let init = "ontable(p, 1, 1), clear(p), ontable(q, 2, 1), clear(q), ontable(r, 4, 1), clear(r), \
                ontable(s, 5, 1), clear(s)";
    let goal = "ontable(p, 2, 1), ontable(q, 1, 1), ontable(r, 5, 1), ontable(s, 4, 1)";
    let mut session = one_arm_problem("trade", &cells, init, goal);
    let row = |x: i64| (x, 1);
    let steps = [
        cycle("r", row(4), row(7)),
        cycle("p", row(1), row(6)),
        cycle("q", row(2), row(1)),
        cycle("p", row(6), row(2)),
        cycle("s", row(5), row(4)),
        cycle("r", row(7), row(5)),
    ]
    .concat();
    let plan = read_plan(&mut session, &steps);
    let mut cost = least_move_duration;
    let mut relocated = |placing: planner::detour::Placing| -> Vec<String> {
        let found = rewritten(&session, |successors, task| {
            planner::detour::relocate(successors, task, &plan, (&[], &[], false), placing, &mut cost)
        })
        .unwrap_or_else(|failure| panic!("{placing:?}: no plan: {failure:?}"));
        let span = session.kb().problems[0].span;
        let verdict = session.validate(0, &PlanStep::of_plan(session.kb(), &found.plan, span));
        assert!(!verdict.diagnostics.has_errors(), "{placing:?}: {:?}", common::messages(&verdict.diagnostics));
        move_starts(&session, &found.plan)
    };
    let in_order = relocated(planner::detour::Placing::InPlanOrder);
    let by_regret = relocated(planner::detour::Placing::ByRegret);
    let has = |moves: &[String], wanted: &str| moves.iter().any(|m| m == wanted);
    assert!(has(&in_order, "move_block_start(a1, r, 4, 1, 3, 1)"), "{in_order:#?}");
    assert!(has(&in_order, "move_block_start(a1, p, 1, 1, 6, 1)"), "{in_order:#?}");
    assert!(has(&by_regret, "move_block_start(a1, p, 1, 1, 3, 1)"), "{by_regret:#?}");
    assert!(has(&by_regret, "move_block_start(a1, r, 4, 1, 6, 1)"), "{by_regret:#?}");
}

#[test]
fn relocating_onto_a_cell_left_later_holds_the_move_s_end_back() {
    // A row of four cells: b1 goes from 3 to 4, where b2 stands, and b2 goes back on top of
    // it. The plan (the search's on build_b02_a3_s5) puts b2 aside on 2 before b1 has even
    // started to leave 3, the nearer cell: 3 + 3 units of moving there and back, against 2 + 2
    // by 3. Sent to 3, b2's move must end after b1's move starts, a later step of the plan;
    // the replay that holds the end back (and b2's release and next grip) takes it there, the
    // plan stays valid and its schedule is shorter. Without holding back, 3 is not offered.
    let cells: Vec<(i64, i64)> = (1..=4).map(|x| (x, 1)).collect();
    let mut text: String = cells.iter().map(|(x, y)| format!("cell({x}, {y}).\n")).collect();
    text.push_str(
        "t :- go(\n  [available(a1), available(a2), ontable(b1, 3, 1), clear(b1), ontable(b2, 4, 1), clear(b2)],\n  \
         [available(a1), available(a2), ontable(b1, 4, 1), on(b2, b1, 4, 1), clear(b2)]\n).\n",
    );
    let mut session = Session::from_text("later.pl", text);
    let steps: Vec<String> = [
        "grip_start(a1, b1)",
        "grip_start(a2, b2)",
        "grip_end(a2, b2)",
        "move_block_start(a2, b2, 4, 1, 2, 1)",
        "move_block_end(a2, b2, 4, 1, 2, 1)",
        "release_start(a2, b2)",
        "release_end(a2, b2)",
        "grip_start(a2, b2)",
        "grip_end(a1, b1)",
        "move_block_start(a1, b1, 3, 1, 4, 1)",
        "move_block_end(a1, b1, 3, 1, 4, 1)",
        "release_start(a1, b1)",
        "release_end(a1, b1)",
        "grip_end(a2, b2)",
        "move_block_start(a2, b2, 2, 1, 4, 1)",
        "move_block_end(a2, b2, 2, 1, 4, 1)",
        "release_start(a2, b2)",
        "release_end(a2, b2)",
    ]
    .map(String::from)
    .to_vec();
    let plan = read_plan(&mut session, &steps);
    let before = timed(&mut session, &plan).schedule;
    let waits = vec![0; plan.steps.len()];
    let mut cost = least_move_duration;
    let mut relocated = |hold_back: bool| {
        let times = &before.earliest[..plan.steps.len()];
        let placing = planner::detour::Placing::InPlanOrder;
        rewritten(&session, |successors, task| {
            planner::detour::relocate(successors, task, &plan, (&waits, times, hold_back), placing, &mut cost)
        })
        .unwrap_or_else(|failure| panic!("holding back {hold_back}: no plan: {failure:?}"))
    };
    let (held, plain) = (relocated(true), relocated(false));
    assert!(plain.taken.is_empty(), "{:#?}", move_starts(&session, &plain.plan));
    let moves = move_starts(&session, &held.plan);
    assert!(moves.iter().any(|m| m == "move_block_start(a2, b2, 4, 1, 3, 1)"), "{moves:#?}");
    let span = session.kb().problems[0].span;
    let verdict = session.validate(0, &PlanStep::of_plan(session.kb(), &held.plan, span));
    assert!(!verdict.diagnostics.has_errors(), "{:?}", common::messages(&verdict.diagnostics));
    let after = timed(&mut session, &held.plan).schedule.makespan;
    assert!(after < before.makespan, "{after} is no shorter than {}", before.makespan);
}

#[test]
fn eliminating_leaves_out_a_trip_out_and_back_and_nothing_the_plan_needs() {
    // b goes from (1, 1) to (2, 1) and c from (3, 1) to (5, 1). After c's move, the plan
    // takes b to (4, 1) and back to (1, 1) for nothing before its move to (2, 1). Left out on
    // trial, b's first grip takes its move and release with it, and its second grip then finds
    // b elsewhere than the plan had it: the whole trip goes, and the state meets the plan's
    // again after it. Nothing else goes: without c's move or b's last one the goal is not
    // reached.
    let cells: Vec<(i64, i64)> = (1..=5).map(|x| (x, 1)).collect();
    let init = "ontable(b, 1, 1), clear(b), ontable(c, 3, 1), clear(c)";
    let goal = "ontable(b, 2, 1), ontable(c, 5, 1)";
    let mut session = one_arm_problem("trip", &cells, init, goal);
    let steps = [
        cycle("c", (3, 1), (5, 1)),
        cycle("b", (1, 1), (4, 1)),
        cycle("b", (4, 1), (1, 1)),
        cycle("b", (1, 1), (2, 1)),
    ]
    .concat();
    let plan = read_plan(&mut session, &steps);
    let found = rewritten(&session, |successors, task| planner::detour::eliminate(successors, task, &plan, 100_000))
        .expect("a valid plan");
    let span = session.kb().problems[0].span;
    let verdict = session.validate(0, &PlanStep::of_plan(session.kb(), &found.plan, span));
    assert!(!verdict.diagnostics.has_errors(), "{:?}", common::messages(&verdict.diagnostics));
    let moves = move_starts(&session, &found.plan);
    assert_eq!(moves, ["move_block_start(a1, c, 3, 1, 5, 1)", "move_block_start(a1, b, 1, 1, 2, 1)"], "{moves:#?}");
    // (The starts of b's two grips, moves and releases.)
    assert_eq!(found.taken, [6, 8, 10, 12, 14, 16]);
    assert_eq!(found.plan.steps.len(), 12);
    // With no budget, nothing is tried.
    let kept = rewritten(&session, |successors, task| planner::detour::eliminate(successors, task, &plan, 0))
        .expect("a valid plan");
    assert!(kept.taken.is_empty() && kept.plan == plan);
}

/// How long the moves of `timed` hold their blocks beyond their least durations, in all.
fn move_waits(session: &Session, timed: &Timed) -> i64 {
    let no_vars = kbc::ir::hir::VarTable::default();
    let earliest = &timed.schedule.earliest;
    timed
        .pop
        .steps
        .iter()
        .enumerate()
        .filter(|(_, step)| {
            kbc::ir::hir::term_to_string(session.interner(), &step.name, &no_vars).starts_with("move_block_end(")
        })
        .filter_map(|(end, step)| {
            let start = step.start?;
            let min = timed.stn.durations[start].map_or(0, |b| b.min);
            Some(earliest[end] - earliest[start] - min)
        })
        .sum()
}

#[test]
fn relocating_counts_the_wait_of_the_place_the_plan_chose() {
    // The search may send a block aside onto a neighbouring cell before the block there has
    // left it: the arm holds the block in the air until then. The cell is the cheapest by
    // its least duration, so relocating kept it; costed with its wait in the plan's schedule,
    // another free cell wins, and the moves wait less in all.
    // (reverse_b12_a4_s1 and reverse_b15_a4_s1 were the rungs here until the backward rules
    // of `reassign` left their moves waiting no more than relocating does.)
    for (blocks, seed) in [(10, 1), (15, 2)] {
        let rung = ladder::Rung { family: ladder::Family::Reverse, blocks, arms: 4, seed };
        let name = rung.name();
        let mut session = Session::from_text(&name, rung.source());
        let (_, (_, jobs), (_, kept)) = rearranged_checked(&mut session, &name, Session::relocate);
        let (before, after) = (move_waits(&session, &jobs), move_waits(&session, &kept));
        assert!(after < before, "{name}: the moves wait {after} after relocating, {before} before");
        assert!(kept.schedule.makespan < jobs.schedule.makespan, "{name}: no shorter");
    }
}

#[test]
fn relocating_starts_keeps_plans_valid_and_moves_shorter() {
    // The search puts blocks aside on whichever free cell comes first, often across the
    // table; relocating sends each to the cheapest free cell instead, its later moves from
    // there. Checked against the independent validator, on rungs where blocks go aside.
    let mut shorter = Vec::new();
    // The least work of the moves of the plans kept, and the time their moves wait (a cell
    // reached at once may be farther than one that is not free yet), before and after.
    let mut work = (0, 0);
    for family in [ladder::Family::Reverse, ladder::Family::Swap] {
        for (blocks, arms) in [(8, 3), (12, 4), (15, 4), (20, 4)] {
            let rung = ladder::Rung { family, blocks, arms, seed: 1 };
            let name = rung.name();
            let mut session = Session::from_text(&name, rung.source());
            let (plan, (_, jobs), (relocated, kept)) = rearranged_checked(&mut session, &name, Session::relocate);
            // The same steps in number: only where blocks go (and who moves them) changes.
            assert_eq!(relocated.steps.len(), plan.steps.len(), "{name}");
            if kept.schedule.makespan < jobs.schedule.makespan {
                let (before, after) = (least_move_work(&session, &plan), least_move_work(&session, &relocated));
                let waits = (move_waits(&session, &jobs), move_waits(&session, &kept));
                work.0 += before * kbc::ir::stn::UNITS + waits.0;
                work.1 += after * kbc::ir::stn::UNITS + waits.1;
                shorter.push(format!(
                    "{name} {} -> {} (moves {before} -> {after}, waiting {} -> {})",
                    jobs.schedule.makespan, kept.schedule.makespan, waits.0, waits.1
                ));
            }
        }
    }
    println!("shorter relocated: {shorter:#?}");
    assert!(shorter.len() >= 3, "only {} plans got shorter: {shorter:?}", shorter.len());
    // Where a relocated plan was kept, its blocks travel and wait less (a plan can also pay
    // by swapping two places of equal cost, or by the reassigning after it).
    assert!(work.1 < work.0, "the relocated plans' moves are no shorter: {work:?}");
}

/// The makespan and origin of `session`'s plan for problem 0 with `settings`; the plan must
/// pass the independent validator.
fn planned_makespan(session: &mut Session, name: &str, settings: &kbc::session::PlanSettings) -> (i64, String) {
    let planned = session.plan(0, settings, &mut Silent).unwrap_or_else(|_| panic!("{name}: a plan"));
    let span = session.kb().problems[0].span;
    let verdict = session.validate(0, &PlanStep::of_plan(session.kb(), planned.plan(), span));
    assert!(!verdict.diagnostics.has_errors(), "{name}: {:?}", common::messages(&verdict.diagnostics));
    (planned.timed.schedule.makespan, planned.origin.clone())
}

#[test]
fn improving_never_ends_longer_than_the_default_run() {
    // By default, where the plain search needed many expansions, a second search that looks
    // ahead runs too and the shorter plan is kept; `--improve` did not run it and could end
    // longer than the default (build_b25_a6: 35 by default, 46 with `--improve 1`).
    let mut second = 0;
    for (blocks, arms) in [(15, 4), (20, 4)] {
        let rung = ladder::Rung { family: ladder::Family::Build, blocks, arms, seed: 1 };
        let name = rung.name();
        let mut session = Session::from_text(&name, rung.source());
        let settings = kbc::session::PlanSettings { timeout: Some(Duration::from_secs(60)), ..Default::default() };
        let (default, origin) = planned_makespan(&mut session, &name, &settings);
        second += origin.contains("lookahead") as usize;
        let improving = kbc::session::PlanSettings { improve: Some(Duration::from_millis(200)), ..settings };
        let (improved, _) = planned_makespan(&mut session, &name, &improving);
        assert!(improved <= default, "{name}: {improved} with --improve, {default} without");
    }
    assert!(second > 0, "no default plan came from the second search: the test tests nothing");
}

#[test]
fn a_restart_with_another_tie_break_can_find_a_shorter_plan() {
    // The search's last tie-break (the depth) decides between states it rates alike; a seeded
    // hash instead leads to another plan, valid too, and here a shorter one (19 -> 17 when
    // written). `--improve` restarts with seeds 1, 2, ... and keeps the shortest.
    let rung = ladder::Rung { family: ladder::Family::Reverse, blocks: 5, arms: 3, seed: 2 };
    let name = rung.name();
    let mut session = Session::from_text(&name, rung.source());
    let settings = kbc::session::PlanSettings { timeout: Some(Duration::from_secs(60)), ..Default::default() };
    let (default, _) = planned_makespan(&mut session, &name, &settings);
    let seeded = kbc::session::PlanSettings { tie_seed: Some(1), ..settings.clone() };
    let (restarted, _) = planned_makespan(&mut session, &name, &seeded);
    assert!(restarted < default, "{name}: {restarted} with seed 1, {default} by default");
    // (The same seed, the same plan.)
    let mut again = Session::from_text(&name, rung.source());
    assert_eq!(planned_makespan(&mut again, &name, &seeded).0, restarted, "{name}: deterministic");
    let improving = kbc::session::PlanSettings { improve: Some(Duration::from_secs(2)), ..settings };
    let (improved, origin) = planned_makespan(&mut session, &name, &improving);
    assert!(improved <= restarted, "{name}: {improved} with --improve, {restarted} from the first restart");
    println!("{name}: {default} by default, {improved} improved ({origin})");
}
