//! What the server keeps between requests: opened documents and built rigs, each under an id,
//! the oldest dropped past a fixed count so that a long session's memory stays bounded.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex};

use splineskin::defop::{DefOpRig, SplineJoin, TrainOptions, Training};
use splineskin::mesh::TriMesh;
use splineskin::scene::Puppet;

use crate::document::Document;

/// Documents kept: 8 (the one given on the command line is kept besides).
pub const MAX_DOCUMENTS: usize = 8;

/// Rigs kept: 4 (and as many operator rigs). A page needs only its latest; a few more serve
/// other tabs.
pub const MAX_RIGS: usize = 4;

/// A built rig: the puppet (weights, rig and, with flexible junctions, the solver and its warm
/// start).
pub struct Rig {
    /// The id of the document it was built on.
    pub document: String,
    /// The puppet; locked while a solve runs.
    pub puppet: Mutex<Puppet>,
}

/// A drawing joined to a deformation operator, with the training behind it (whose operator's
/// mesh deformation, [`splineskin::defop::MeshMap`], carries what is not a curve on export,
/// and which following the user extends: `POST /api/defops/{id}/follow`).
pub struct OperatorRig {
    /// The id of the document it was trained on.
    pub document: String,
    /// The join: the drawing's control points as `G_spline ψ(Q)`.
    pub rig: DefOpRig,
    /// The operator with its samples and their ground truths.
    pub training: Training,
    /// What every operator followed from the same training shares.
    pub base: Arc<OperatorBase>,
}

/// What an operator and those that follow the user from it share: the mesh, the training's
/// options, the operator-free half of the join, and the trained region.
pub struct OperatorBase {
    /// The mesh the operator was trained on.
    pub mesh: TriMesh,
    /// The training's options (energy, solvers, fit).
    pub options: TrainOptions,
    /// The drawing's fit over the mesh: an operator's join is then products only.
    pub join: SplineJoin,
    /// Samples of the first training, the rest included: the region the scene asked for.
    pub n_trained: usize,
    /// The sampling radius ([`TrainOptions::reach`]), root user units.
    pub reach: f64,
}

/// Items kept under ids, newest last, the oldest dropped past `limit`.
struct Kept<T> {
    items: VecDeque<(String, Arc<T>)>,
    limit: usize,
}

impl<T> Kept<T> {
    fn new(limit: usize) -> Self {
        Self {
            items: VecDeque::new(),
            limit,
        }
    }

    /// Keeps `item` under `id`, dropping the oldest past the limit; returns the kept item.
    fn add(&mut self, id: String, item: T) -> Arc<T> {
        let item = Arc::new(item);
        self.items.push_back((id, item.clone()));
        while self.items.len() > self.limit {
            self.items.pop_front();
        }
        item
    }

    fn iter(&self) -> impl Iterator<Item = &(String, Arc<T>)> {
        self.items.iter()
    }

    /// Drops the item `id`, if kept.
    fn remove(&mut self, id: &str) {
        self.items.retain(|(k, _)| k != id);
    }

    /// The item `id`, if kept.
    fn get(&self, id: &str) -> Option<Arc<T>> {
        self.iter()
            .find(|(k, _)| k == id)
            .map(|(_, item)| item.clone())
    }
}

/// Documents and rigs by id.
pub struct Store {
    next_id: u64,
    /// The document given on the command line (or the bundled one), never dropped.
    initial: Option<(String, Arc<Document>)>,
    documents: Kept<Document>,
    rigs: Kept<Rig>,
    defops: Kept<OperatorRig>,
}

impl Default for Store {
    fn default() -> Self {
        Self {
            next_id: 0,
            initial: None,
            documents: Kept::new(MAX_DOCUMENTS),
            rigs: Kept::new(MAX_RIGS),
            defops: Kept::new(MAX_RIGS),
        }
    }
}

impl Store {
    fn new_id(&mut self, prefix: char) -> String {
        self.next_id += 1;
        format!("{prefix}{}", self.next_id)
    }

    /// Keeps `document` as the initial one; returns its id.
    pub fn set_initial(&mut self, mut document: Document) -> String {
        let id = self.new_id('d');
        document.info.id = id.clone();
        self.initial = Some((id.clone(), Arc::new(document)));
        id
    }

    /// The initial document.
    pub fn initial(&self) -> Option<Arc<Document>> {
        self.initial.as_ref().map(|(_, d)| d.clone())
    }

    /// Keeps `document`, dropping the oldest past [`MAX_DOCUMENTS`]; returns it with its id
    /// set.
    pub fn add_document(&mut self, mut document: Document) -> Arc<Document> {
        let id = self.new_id('d');
        document.info.id = id.clone();
        self.documents.add(id, document)
    }

    /// The document `id`, if kept.
    pub fn document(&self, id: &str) -> Option<Arc<Document>> {
        self.initial
            .iter()
            .chain(self.documents.iter())
            .find(|(k, _)| k == id)
            .map(|(_, d)| d.clone())
    }

    /// Keeps a rig built on document `document`, dropping the oldest past [`MAX_RIGS`];
    /// returns its id.
    pub fn add_rig(&mut self, document: &str, puppet: Puppet) -> String {
        let id = self.new_id('r');
        let rig = Rig {
            document: document.to_string(),
            puppet: Mutex::new(puppet),
        };
        self.rigs.add(id.clone(), rig);
        id
    }

    /// The rig `id`, if kept.
    pub fn rig(&self, id: &str) -> Option<Arc<Rig>> {
        self.rigs.get(id)
    }

    /// Keeps a drawing joined to a deformation operator, dropping the oldest past
    /// [`MAX_RIGS`]; returns its id.
    pub fn add_defop(&mut self, rig: OperatorRig) -> String {
        let id = self.new_id('o');
        self.defops.add(id.clone(), rig);
        id
    }

    /// The operator rig `id`, if kept.
    pub fn defop(&self, id: &str) -> Option<Arc<OperatorRig>> {
        self.defops.get(id)
    }

    /// Drops rig `id` (after a solve panicked while holding it).
    pub fn remove_rig(&mut self, id: &str) {
        self.rigs.remove(id);
    }
}
