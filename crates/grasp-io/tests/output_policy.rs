//! The output policy, class by class (each with several cases): targets that are not regular
//! files are refused even with force; an existing file needs force; an input is never an
//! output, however it is named; two names of one output are refused; outputs are moved into
//! place without replacing a file that appeared meanwhile; every output is locked for the run
//! and the refusal names the holder; missing folders are created (and said) or refused; failed
//! runs leave no hidden file behind; threads writing the same output never mix their bytes.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

use grasp_io::{OutputErrorKind, OutputRules, OutputSet, RunInputs};

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("grasp-io-out-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

const FORCE: OutputRules = OutputRules {
    force: true,
    create_folders: false,
};
const KEEP: OutputRules = OutputRules {
    force: false,
    create_folders: false,
};

/// Hidden files (temporary or lock) left in `dir`.
fn hidden(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".grasp-"))
        .collect()
}

fn claim(
    target: &Path,
    inputs: &RunInputs,
    rules: OutputRules,
) -> Result<OutputSet, grasp_io::OutputError> {
    OutputSet::claim(&[target], inputs, rules)
}

#[test]
fn targets_that_are_not_regular_files_are_refused_even_with_force() {
    let d = scratch("kinds");
    let real = d.join("real.csv");
    std::fs::write(&real, "precious").unwrap();
    let link = d.join("link.csv");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    let dangling = d.join("dangling.csv");
    std::os::unix::fs::symlink(d.join("nowhere.csv"), &dangling).unwrap();
    let dev_link = d.join("devnull.csv");
    std::os::unix::fs::symlink("/dev/null", &dev_link).unwrap();
    let socket = d.join("sock.csv");
    let _listener = std::os::unix::net::UnixListener::bind(&socket).unwrap();
    let mut cases: Vec<(PathBuf, &str)> = vec![
        (d.join("sub"), "is a folder"),
        (link.clone(), "is a symbolic link"),
        (dangling.clone(), "dangling"),
        (dev_link, "is a symbolic link"),
        ("/dev/null".into(), "not a regular file (a device)"),
        (socket, "not a regular file (a socket)"),
        (d.join(".."), "does not name a file"),
    ];
    std::fs::create_dir_all(d.join("sub")).unwrap();
    let fifo = d.join("pipe.csv");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.as_ref().is_ok_and(|s| s.success()), "mkfifo: {made:?}");
    cases.push((fifo, "a FIFO"));
    for (target, words) in &cases {
        for rules in [KEEP, FORCE] {
            let e = claim(target, &RunInputs::new(), rules).unwrap_err();
            assert_eq!(e.kind, OutputErrorKind::Refused, "{target:?}: {e}");
            assert!(e.to_string().contains(words), "{target:?}: {e}");
        }
    }
    assert_eq!(std::fs::read_to_string(&real).unwrap(), "precious");
    assert!(std::fs::symlink_metadata(&dangling)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(
        !d.join("nowhere.csv").exists(),
        "a dangling link was followed"
    );
    assert!(hidden(&d).is_empty(), "{:?}", hidden(&d));
}

#[test]
fn an_existing_file_is_replaced_only_with_force() {
    let d = scratch("exists");
    let target = d.join("a.json");
    std::fs::write(&target, "mine").unwrap();
    let e = claim(&target, &RunInputs::new(), KEEP).unwrap_err();
    assert_eq!(e.kind, OutputErrorKind::Exists);
    assert!(e.to_string().contains("pass `OutputRules::force`"), "{e}");
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "mine");
    let set = claim(&target, &RunInputs::new(), FORCE).unwrap();
    set.write(&target, b"new").unwrap();
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
    drop(set);
    assert!(hidden(&d).is_empty(), "{:?}", hidden(&d));
}

#[test]
fn an_input_is_never_an_output_however_it_is_named() {
    let d = scratch("inputs");
    std::fs::create_dir_all(d.join("sub")).unwrap();
    let scene = d.join("scene.json");
    std::fs::write(&scene, "{}").unwrap();
    let sym = d.join("scene-link.json");
    std::os::unix::fs::symlink(&scene, &sym).unwrap();
    let hard = d.join("scene-hard.json");
    std::fs::hard_link(&scene, &hard).unwrap();
    let dir_link = d.join("dirlink");
    std::os::unix::fs::symlink(&d, &dir_link).unwrap();
    // The run read the scene through the link (identity of the file reached).
    let mut inputs = RunInputs::new();
    inputs.add_existing(&sym);
    for target in [
        scene.clone(),
        hard.clone(),
        d.join("sub/../scene.json"),
        dir_link.join("scene.json"),
    ] {
        let e = claim(&target, &inputs, FORCE).unwrap_err();
        assert!(
            e.to_string().contains("is also an input of this command"),
            "{target:?}: {e}"
        );
    }
    // Learned after the claim (a mesh, a CSV profile): refused before anything is moved.
    let other = d.join("profile.csv");
    std::fs::write(&other, "t,p\n").unwrap();
    let set = claim(&other, &RunInputs::new(), FORCE).unwrap();
    let mut later = RunInputs::new();
    later.add_existing(&other);
    let e = set.refuse_inputs(&later).unwrap_err();
    assert!(e.to_string().contains("is also an input"), "{e}");
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), "{}");
    assert_eq!(std::fs::read_to_string(&other).unwrap(), "t,p\n");
}

#[test]
fn two_names_of_one_output_are_refused() {
    let d = scratch("twice");
    std::fs::create_dir_all(d.join("sub")).unwrap();
    let a = d.join("x.out");
    let existing = d.join("y.out");
    std::fs::write(&existing, "y").unwrap();
    let hard = d.join("y-hard.out");
    std::fs::hard_link(&existing, &hard).unwrap();
    let missing_folder = d.join("new/x.out");
    for (first, second) in [
        (a.clone(), d.join("sub/../x.out")),
        (a.clone(), d.join("./x.out")),
        (existing.clone(), hard.clone()),
        (missing_folder.clone(), d.join("new/../new/./x.out")),
    ] {
        let e = OutputSet::claim(&[&first, &second], &RunInputs::new(), FORCE).unwrap_err();
        assert!(
            e.to_string().contains("is also another output"),
            "{first:?} {second:?}: {e}"
        );
    }
    assert!(!a.exists() && !d.join("new").exists());
}

#[test]
fn a_file_that_appears_meanwhile_is_never_replaced_without_force() {
    let d = scratch("appear");
    let target = d.join("r.csv");
    let set = claim(&target, &RunInputs::new(), KEEP).unwrap();
    let mut p = set.create(&target).unwrap();
    p.write_all(b"ours").unwrap();
    // Another program creates the file (regular, or a link) while the run writes.
    std::fs::write(&target, "theirs").unwrap();
    let e = set.commit(vec![p]).unwrap_err();
    assert_eq!(e.kind, OutputErrorKind::Exists);
    assert!(e.to_string().contains("appeared while the run"), "{e}");
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "theirs");
    std::fs::remove_file(&target).unwrap();
    let victim = d.join("victim.txt");
    std::fs::write(&victim, "keep").unwrap();
    let p = set.create(&target).unwrap();
    std::os::unix::fs::symlink(&victim, &target).unwrap();
    assert!(set.commit(vec![p]).is_err());
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep");
    drop(set);
    // With force, a link planted meanwhile is not replaced either.
    std::fs::remove_file(&target).unwrap();
    let set = claim(&target, &RunInputs::new(), FORCE).unwrap();
    let p = set.create(&target).unwrap();
    std::os::unix::fs::symlink(&victim, &target).unwrap();
    let e = set.commit(vec![p]).unwrap_err();
    assert!(e.to_string().contains("is a symbolic link"), "{e}");
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep");
    drop(set);
    assert!(hidden(&d).is_empty(), "{:?}", hidden(&d));
}

#[test]
fn temporary_files_are_fresh_hidden_regular_files_beside_the_target() {
    let d = scratch("tmp");
    let target = d.join("m.mcap");
    let set = claim(&target, &RunInputs::new(), KEEP).unwrap();
    let mut names = std::collections::HashSet::new();
    for _ in 0..200 {
        let p = set.create(&target).unwrap();
        let name = p.tmp().file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.starts_with(".m.mcap.grasp-tmp-"), "{name}");
        assert_eq!(p.tmp().parent(), Some(d.as_path()));
        assert!(std::fs::symlink_metadata(p.tmp())
            .unwrap()
            .file_type()
            .is_file());
        assert!(names.insert(name), "a temporary name repeated");
    }
    // A writer that opens a path itself reaches the temporary file through write_path.
    let p = set.create(&target).unwrap();
    File::create(p.write_path())
        .unwrap()
        .write_all(b"through the descriptor")
        .unwrap();
    assert_eq!(
        std::fs::read_to_string(p.tmp()).unwrap(),
        "through the descriptor"
    );
    // Not committed: removed.
    let tmp = p.tmp().to_path_buf();
    drop(p);
    assert!(!tmp.exists());
    // A claim is needed before writing.
    let e = set.create(&d.join("other")).unwrap_err();
    assert!(e.to_string().contains("was not checked and locked"), "{e}");
}

#[test]
fn every_output_is_locked_and_the_refusal_names_the_holder() {
    let d = scratch("lock");
    let target = d.join("results.jsonl");
    let first = claim(&target, &RunInputs::new(), FORCE).unwrap();
    let lock_file = d.join(".results.jsonl.grasp-lock");
    assert_eq!(
        std::fs::read_to_string(&lock_file).unwrap().trim(),
        std::process::id().to_string()
    );
    let e = claim(&target, &RunInputs::new(), FORCE).unwrap_err();
    assert_eq!(e.kind, OutputErrorKind::Locked);
    assert!(
        e.to_string()
            .contains("another run of grasp in this process"),
        "{e}"
    );
    drop(first);
    assert!(!lock_file.exists(), "the lock file outlived its run");
    // Held by another process (its id written in the lock file): named.
    let held = File::options()
        .read(true)
        .write(true)
        .create(true)
        .truncate(true)
        .open(&lock_file)
        .unwrap();
    held.lock().unwrap();
    (&held).write_all(b"4242\n").unwrap();
    let e = claim(&target, &RunInputs::new(), FORCE).unwrap_err();
    assert!(e.to_string().contains("process 4242"), "{e}");
    held.unlock().unwrap();
    drop(held);
    // A lock file left by a killed run (not locked) is taken over.
    let set = claim(&target, &RunInputs::new(), FORCE).unwrap();
    drop(set);
    // A lock file that is a link or a folder is refused, and not followed.
    let victim = d.join("victim");
    std::fs::write(&victim, "keep").unwrap();
    std::os::unix::fs::symlink(&victim, &lock_file).unwrap();
    let e = claim(&target, &RunInputs::new(), FORCE).unwrap_err();
    assert!(e.to_string().contains("not a lock file of grasp"), "{e}");
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep");
    std::fs::remove_file(&lock_file).unwrap();
    std::fs::create_dir(&lock_file).unwrap();
    let e = claim(&target, &RunInputs::new(), FORCE).unwrap_err();
    assert!(e.to_string().contains("not a lock file of grasp"), "{e}");
}

#[test]
fn missing_folders_are_created_when_allowed_and_removed_when_the_claim_fails() {
    let d = scratch("folders");
    let target = d.join("a/b/c.csv");
    let e = claim(&target, &RunInputs::new(), KEEP).unwrap_err();
    assert_eq!(e.kind, OutputErrorKind::MissingFolder);
    assert!(e.to_string().contains("does not exist"), "{e}");
    assert!(!d.join("a").exists());
    let rules = OutputRules {
        force: false,
        create_folders: true,
    };
    let set = claim(&target, &RunInputs::new(), rules).unwrap();
    assert_eq!(set.created_folders(), [d.join("a"), d.join("a/b")]);
    set.write(&target, b"x").unwrap();
    drop(set);
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "x");
    // The second target is locked by someone else: the folder made for the first goes again.
    let busy = d.join("busy.csv");
    let holder = claim(&busy, &RunInputs::new(), rules).unwrap();
    let fresh = d.join("new/f.csv");
    let e = OutputSet::claim(&[&fresh, &busy], &RunInputs::new(), rules).unwrap_err();
    assert_eq!(e.kind, OutputErrorKind::Locked);
    assert!(!d.join("new").exists());
    drop(holder);
    // A path through a file is no folder.
    let e = claim(&target.join("x"), &RunInputs::new(), rules).unwrap_err();
    assert!(e.to_string().contains("is not a folder"), "{e}");
}

#[test]
fn threads_writing_one_output_never_mix_their_bytes() {
    let d = scratch("threads");
    let target = d.join("shared.csv");
    let outcomes: Vec<Result<(), String>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..4)
            .map(|k| {
                let target = target.clone();
                s.spawn(move || {
                    let set =
                        claim(&target, &RunInputs::new(), FORCE).map_err(|e| e.to_string())?;
                    let mut p = set.create(&target).map_err(|e| e.to_string())?;
                    for _ in 0..2000 {
                        p.write_all(format!("{k},{k},{k}\n").as_bytes())
                            .map_err(|e| e.to_string())?;
                    }
                    set.commit(vec![p]).map_err(|e| e.to_string())
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert!(outcomes.iter().any(Result::is_ok), "{outcomes:?}");
    for o in &outcomes {
        if let Err(e) = o {
            assert!(
                e.contains("is being written by another run of grasp"),
                "{e}"
            );
        }
    }
    let text = std::fs::read_to_string(&target).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2000);
    assert!(lines.iter().all(|l| *l == lines[0]), "mixed writers");
    assert!(hidden(&d).is_empty(), "{:?}", hidden(&d));
}
